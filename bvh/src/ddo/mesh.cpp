#include "logrid/ddo/mesh.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

namespace logrid::ddo {

std::string validateSceneMesh(const SceneMesh& mesh) {
  std::ostringstream out;
  if (!mesh.positions || !mesh.indices || !mesh.object_first) {
    return "ddo: the scene mesh is missing its positions, indices or object runs";
  }
  const std::vector<float>& p = *mesh.positions;
  const std::vector<std::uint32_t>& idx = *mesh.indices;
  const std::vector<std::uint32_t>& obj = *mesh.object_first;
  if (p.size() % 3 != 0 || idx.size() % 3 != 0) {
    return "ddo: positions and indices must come in threes (xyz, and three per triangle)";
  }
  const std::size_t triangles = idx.size() / 3, vertices = p.size() / 3;
  if (triangles == 0) return "ddo: the scene has no triangle";
  if (triangles >= std::numeric_limits<std::uint32_t>::max() - 1) {
    return "ddo: too many triangles (at most 2^32 - 2)";
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!std::isfinite(p[i])) {
      out << "ddo: vertex " << i / 3 << " has a non-finite coordinate ("
          << "xyz"[i % 3] << " = " << p[i] << "); positions must be finite";
      return out.str();
    }
  }
  for (std::size_t i = 0; i < idx.size(); ++i) {
    if (idx[i] >= vertices) {
      out << "ddo: triangle " << i / 3 << " uses vertex " << idx[i] << " but there are only "
          << vertices << " vertices";
      return out.str();
    }
  }
  if (obj.size() < 2 || obj.front() != 0 || obj.back() != triangles) {
    out << "ddo: object runs must start at triangle 0 and end at the triangle count " << triangles
        << " (got " << obj.size() << " entries";
    if (!obj.empty()) out << ", first " << obj.front() << ", last " << obj.back();
    out << ")";
    return out.str();
  }
  for (std::size_t o = 0; o + 1 < obj.size(); ++o) {
    if (obj[o + 1] < obj[o]) {
      out << "ddo: object " << o << " ends (" << obj[o + 1] << ") before it starts (" << obj[o]
          << ")";
      return out.str();
    }
  }
  return {};
}

namespace {

// A 64-bit multiply-xorshift mix over 8-byte words: fast and good enough to tell a scene
// from an edited one (it is a staleness check, not a cryptographic one).
class Hasher {
 public:
  void add(const void* data, std::size_t bytes) {
    if (bytes == 0) return;
    const auto* p = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 8 <= bytes; i += 8) {
      std::uint64_t w;
      std::memcpy(&w, p + i, 8);
      mix(w);
    }
    std::uint64_t tail = 0;
    if (bytes > i) std::memcpy(&tail, p + i, bytes - i);
    mix(tail ^ (std::uint64_t(bytes - i) << 56));
  }
  std::uint64_t value() const { return h_ ^ (h_ >> 29); }

 private:
  void mix(std::uint64_t w) {
    w *= 0x9E3779B97F4A7C15ull;
    w ^= w >> 32;
    h_ = (h_ ^ w) * 0xD6E8FEB86659FD93ull;
    h_ ^= h_ >> 32;
  }
  std::uint64_t h_ = 0x6A09E667F3BCC909ull;
};

}  // namespace

std::uint64_t sceneChecksum(const SceneMesh& mesh) {
  Hasher h;
  const std::uint64_t sizes[3] = {mesh.positions->size(), mesh.indices->size(),
                                  mesh.object_first->size()};
  h.add(sizes, sizeof sizes);
  h.add(mesh.positions->data(), mesh.positions->size() * sizeof(float));
  h.add(mesh.indices->data(), mesh.indices->size() * sizeof(std::uint32_t));
  h.add(mesh.object_first->data(), mesh.object_first->size() * sizeof(std::uint32_t));
  return h.value();
}

}  // namespace logrid::ddo
