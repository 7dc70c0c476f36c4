#include "topology.hpp"

#include <algorithm>
#include <cstring>
#include <thread>

namespace logrid::ddo::detail {
namespace {

std::uint32_t floatBits(float f) {
  f += 0.0f;  // -0 becomes +0
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

std::uint64_t hashPosition(const float* p) {
  std::uint64_t h = floatBits(p[0]) * 0x9E3779B97F4A7C15ull;
  h ^= (h >> 29) + floatBits(p[1]) * 0xBF58476D1CE4E5B9ull;
  h ^= (h >> 31) + floatBits(p[2]) * 0x94D049BB133111EBull;
  return h ^ (h >> 32);
}

bool samePosition(const float* a, const float* b) {
  return floatBits(a[0]) == floatBits(b[0]) && floatBits(a[1]) == floatBits(b[1]) &&
         floatBits(a[2]) == floatBits(b[2]);
}

// Runs body(begin, end) over [0, n) split into `threads` contiguous parts.
template <typename Body>
void parallelFor(std::size_t n, unsigned threads, const Body& body) {
  if (threads <= 1 || n < 100000) {
    body(std::size_t{0}, n);
    return;
  }
  std::vector<std::thread> pool;
  for (unsigned i = 0; i < threads; ++i) {
    const std::size_t b = n * i / threads, e = n * (i + 1) / threads;
    pool.emplace_back([&body, b, e] { body(b, e); });
  }
  for (std::thread& t : pool) t.join();
}

}  // namespace

MeshTopology::MeshTopology(const SceneMesh& mesh, unsigned threads) {
  const std::size_t vertices = mesh.vertexCount(), triangles = mesh.triangleCount();

  // Welding: canonical[v] is the first vertex with v's position.
  std::vector<std::uint32_t> canonical(vertices);
  {
    std::size_t slots = 16;
    while (slots < vertices * 2) slots *= 2;
    std::vector<std::uint32_t> table(slots, 0);  // vertex + 1, 0 = empty
    build_bytes_ = table.capacity() * 4 + canonical.capacity() * 4;
    for (std::uint32_t v = 0; v < vertices; ++v) {
      const float* p = mesh.vertex(v);
      std::size_t s = hashPosition(p) & (slots - 1);
      for (;; s = (s + 1) & (slots - 1)) {
        if (table[s] == 0) {
          table[s] = v + 1;
          canonical[v] = v;
          break;
        }
        if (samePosition(mesh.vertex(table[s] - 1), p)) {
          canonical[v] = table[s] - 1;
          break;
        }
      }
    }
  }
  auto welded = [&](std::size_t t, int k) { return canonical[mesh.corner(t, k)]; };

  degenerate_.assign((triangles + 63) / 64, 0);
  for (std::size_t t = 0; t < triangles; ++t) {
    const std::uint32_t a = welded(t, 0), b = welded(t, 1), c = welded(t, 2);
    if (a == b || b == c || a == c) degenerate_[t >> 6] |= std::uint64_t{1} << (t & 63);
  }

  // Vertex-to-triangle lists over welded vertices (non-degenerate triangles only, so a
  // triangle appears once in the list of each of its corners).
  std::vector<std::uint32_t> first(vertices + 1, 0);
  for (std::size_t t = 0; t < triangles; ++t) {
    if (degenerate(std::uint32_t(t))) continue;
    for (int k = 0; k < 3; ++k) ++first[welded(t, k) + 1];
  }
  for (std::size_t v = 0; v < vertices; ++v) first[v + 1] += first[v];
  std::vector<std::uint32_t> incident(first[vertices]);
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t t = 0; t < triangles; ++t) {
      if (degenerate(std::uint32_t(t))) continue;
      for (int k = 0; k < 3; ++k) incident[fill[welded(t, k)]++] = std::uint32_t(t);
    }
  }
  build_bytes_ = std::max(build_bytes_, canonical.capacity() * 4 + first.capacity() * 4 +
                                            incident.capacity() * 4 + triangles * 12);

  // next(h): the smallest member of h's edge group above h, else the smallest member.
  next_.resize(triangles * 3);
  parallelFor(triangles, threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t h = std::uint32_t(t * 3 + std::size_t(k));
        if (degenerate(std::uint32_t(t))) {
          next_[h] = h;
          continue;
        }
        const std::uint32_t a = welded(t, k), b = welded(t, (k + 1) % 3);
        std::uint32_t above = h, smallest = h;
        bool found_above = false;
        for (std::uint32_t i = first[a]; i < first[a + 1]; ++i) {
          const std::uint32_t t2 = incident[i];
          for (int k2 = 0; k2 < 3; ++k2) {
            const std::uint32_t a2 = welded(t2, k2), b2 = welded(t2, (k2 + 1) % 3);
            if (!((a2 == a && b2 == b) || (a2 == b && b2 == a))) continue;
            const std::uint32_t h2 = t2 * 3 + std::uint32_t(k2);
            smallest = std::min(smallest, h2);
            if (h2 > h && (!found_above || h2 < above)) above = h2, found_above = true;
          }
        }
        next_[h] = found_above ? above : smallest;
      }
    }
  });
}

}  // namespace logrid::ddo::detail
