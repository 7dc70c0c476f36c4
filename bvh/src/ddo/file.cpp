#include "logrid/ddo/file.hpp"

#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

namespace logrid::ddo {
namespace {

constexpr char kMagic[8] = {'l', 'o', 'g', 'r', 'd', 'D', 'D', 'O'};

class Writer {
 public:
  template <typename T>
  void put(const T& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void putBytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    bytes_.insert(bytes_.end(), b, b + n);
  }
  std::vector<unsigned char>& bytes() { return bytes_; }

 private:
  std::vector<unsigned char> bytes_;
};

// Reads the file's fields in order. The first failure is kept (status()); reads after
// it yield zeros and move nothing, so a caller checks failed() before it uses what it
// read for sizes or indices.
class Reader {
 public:
  Reader(const std::vector<unsigned char>& bytes, std::size_t end, const std::string& path)
      : bytes_(bytes), end_(end), path_(path) {}
  template <typename T>
  T get() {
    T v{};
    getBytes(&v, sizeof(T));
    return v;
  }
  void getBytes(void* out, std::size_t n) {
    if (n == 0) return;  // `out` may be the null data() of an empty list (memcpy's contract)
    if (!failed() && n > end_ - at_) (void)fail("is truncated");  // kept in status()
    if (failed()) {
      std::memset(out, 0, n);
      return;
    }
    std::memcpy(out, bytes_.data() + at_, n);
    at_ += n;
  }
  std::size_t left() const { return end_ - at_; }
  // Records `what` as the failure unless one came first; returns the first.
  Status fail(const std::string& what) {
    if (status_.ok()) {
      status_ = Status(ErrorCode::BadInput, "DDO file '" + path_ + "' " + what +
                                                "; delete it or rebuild it (logrid ddo --rebuild)");
    }
    return status_;
  }
  bool failed() const { return !status_.ok(); }
  const Status& status() const { return status_; }

 private:
  const std::vector<unsigned char>& bytes_;
  std::size_t end_;
  std::size_t at_ = 0;
  const std::string& path_;
  Status status_;
};

std::size_t maskBytesPerFace(std::uint32_t regions) { return regions / 8; }

}  // namespace

std::uint64_t payloadChecksum(const unsigned char* data, std::size_t bytes) {
  std::uint64_t h = 0xCBF29CE484222325ull;  // FNV-1a over 8-byte words, then bytes
  std::size_t i = 0;
  for (; i + 8 <= bytes; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, data + i, 8);
    h = (h ^ w) * 0x100000001B3ull;
    h ^= h >> 31;
  }
  for (; i < bytes; ++i) h = (h ^ data[i]) * 0x100000001B3ull;
  return h;
}

Status trySaveOctree(const Octree& octree, const FileExpectation& scene, const std::string& path) {
  Writer w;
  w.putBytes(kMagic, sizeof kMagic);
  w.put(kFileVersion);
  w.put(scene.scene_checksum);
  w.put(scene.triangles);
  w.put(scene.objects);
  const OctreeParams& p = octree.params();
  for (double v : p.root_lo) w.put(v);
  w.put(p.root_side);
  w.put(p.regions);
  w.put(p.leaf_triangles);
  w.put(p.max_depth);
  w.put(p.face_margin);
  w.put(std::uint64_t(octree.nodes().size()));
  w.put(std::uint64_t(octree.objects().size()));
  for (const OctreeNode& n : octree.nodes()) {
    const float box[6] = {n.bounds.min.x, n.bounds.min.y, n.bounds.min.z,
                          n.bounds.max.x, n.bounds.max.y, n.bounds.max.z};
    w.putBytes(box, sizeof box);
    w.putBytes(n.cell, sizeof n.cell);
    w.put(n.first_child);
    w.put(n.first_object);
    w.put(n.object_count);
    w.put(n.triangle_count);
    w.put(n.level);
    w.put(n.child_mask);
  }
  w.putBytes(octree.objects().data(), octree.objects().size() * sizeof(ObjectId));
  const std::size_t per_face = maskBytesPerFace(p.regions);
  for (std::uint64_t m : octree.masks()) w.putBytes(&m, per_face);  // little-endian low bytes
  const std::uint64_t sum = payloadChecksum(w.bytes().data(), w.bytes().size());
  w.put(sum);

  const std::string temporary = path + ".partial";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) {
      return Status(ErrorCode::Environment, "cannot write the DDO file '" + temporary +
                                                "': check that its folder exists and is writable");
    }
    out.write(reinterpret_cast<const char*>(w.bytes().data()), std::streamsize(w.bytes().size()));
    if (!out.flush()) {
      return Status(ErrorCode::Environment,
                    "writing the DDO file '" + temporary + "' failed (disk full?)");
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    return Status(ErrorCode::Environment, "cannot rename '" + temporary + "' to '" + path + "'");
  }
  return {};
}

namespace {

Result<std::vector<unsigned char>> readWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) {
    return Status(ErrorCode::Environment,
                  "cannot read the DDO file '" + path + "': check the path and its permissions");
  }
  const std::streamoff size = in.tellg();
  std::vector<unsigned char> bytes(size > 0 ? std::size_t(size) : 0);
  in.seekg(0);
  if (!bytes.empty()) in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!in) return Status(ErrorCode::Environment, "reading the DDO file '" + path + "' failed");
  return bytes;
}

// The magic, the version and the checksum; returns the size of the checked payload.
Result<std::size_t> checkEnvelope(const std::vector<unsigned char>& bytes,
                                  const std::string& path) {
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
    return Status(ErrorCode::BadInput, "'" + path +
                                           "' is not a DDO file (its first bytes are not "
                                           "\"logrdDDO\"); pass the .ddo file logrid wrote");
  }
  Reader header(bytes, bytes.size(), path);
  {
    char magic[8];
    header.getBytes(magic, 8);
  }
  const auto version = header.get<std::uint32_t>();
  if (header.failed()) return header.status();
  if (version != kFileVersion) {
    std::ostringstream out;
    out << "has format version " << version << ", this logrid reads version " << kFileVersion;
    return header.fail(out.str());
  }
  if (bytes.size() < 8 + 4 + 8) return header.fail("is truncated");
  const std::size_t body = bytes.size() - 8;
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + body, 8);
  if (stored != payloadChecksum(bytes.data(), body)) {
    return header.fail("is corrupt (checksum mismatch)");
  }
  return body;
}

// The scene the file was built for, and the octree's parameters, against what is asked.
Result<OctreeParams> readParams(Reader& r, const FileExpectation& expect) {
  {
    char magic[8];
    r.getBytes(magic, 8);
    r.get<std::uint32_t>();
  }
  const auto checksum = r.get<std::uint64_t>();
  const auto triangles = r.get<std::uint64_t>();
  const auto objects = r.get<std::uint64_t>();
  if (r.failed()) return r.status();
  if (checksum != expect.scene_checksum || triangles != expect.triangles ||
      objects != expect.objects) {
    std::ostringstream out;
    out << "is stale: it was built for another scene (" << triangles << " triangles, " << objects
        << " objects, checksum " << std::hex << checksum << std::dec << "; this scene has "
        << expect.triangles << " triangles, " << expect.objects << " objects, checksum " << std::hex
        << expect.scene_checksum << std::dec << ")";
    return r.fail(out.str());
  }
  OctreeParams p;
  for (double& v : p.root_lo) v = r.get<double>();
  p.root_side = r.get<double>();
  p.regions = r.get<std::uint32_t>();
  p.leaf_triangles = r.get<std::uint32_t>();
  p.max_depth = r.get<std::uint32_t>();
  p.face_margin = r.get<double>();
  if (r.failed()) return r.status();
  if (!RegionLayout::forCount(p.regions) || !(p.root_side > 0) || p.max_depth > 24 ||
      !(p.face_margin >= 0)) {
    return r.fail("has invalid parameters");
  }
  if ((expect.regions && expect.regions != p.regions) ||
      (expect.leaf_triangles && expect.leaf_triangles != p.leaf_triangles)) {
    std::ostringstream out;
    out << "was built with " << p.regions << " regions and " << p.leaf_triangles
        << " triangles per leaf, not the " << (expect.regions ? expect.regions : p.regions)
        << " and " << (expect.leaf_triangles ? expect.leaf_triangles : p.leaf_triangles)
        << " asked for";
    return r.fail(out.str());
  }
  return p;
}

std::vector<OctreeNode> readNodes(Reader& r, std::uint64_t count) {
  std::vector<OctreeNode> nodes(count);
  for (OctreeNode& n : nodes) {
    float box[6];
    r.getBytes(box, sizeof box);
    n.bounds = {{box[0], box[1], box[2]}, {box[3], box[4], box[5]}};
    r.getBytes(n.cell, sizeof n.cell);
    n.first_child = r.get<std::uint32_t>();
    n.first_object = r.get<std::uint32_t>();
    n.object_count = r.get<std::uint32_t>();
    n.triangle_count = r.get<std::uint32_t>();
    n.level = r.get<std::uint8_t>();
    n.child_mask = r.get<std::uint8_t>();
  }
  return nodes;
}

// The structure must be one the run time can walk without checks.
Status checkStructure(const std::vector<OctreeNode>& nodes, const std::vector<ObjectId>& objects,
                      const OctreeParams& p, const FileExpectation& expect, Reader& r) {
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const OctreeNode& n = nodes[i];
    const bool bad_children =
        !n.leaf() &&
        (n.first_child <= i || n.first_child + std::uint64_t(n.childCount()) > nodes.size());
    const bool bad_objects = std::uint64_t(n.first_object) + n.object_count > objects.size();
    const bool bad_level = n.level > p.max_depth || (i == 0 && n.level != 0);
    if (bad_children || bad_objects || bad_level) {
      std::ostringstream out;
      out << "describes an inconsistent octree (node " << i << ")";
      return r.fail(out.str());
    }
    std::uint32_t c = n.first_child;
    for (int octant = 0; octant < 8; ++octant) {
      if (!((n.child_mask >> octant) & 1u)) continue;
      const OctreeNode& child = nodes[c++];
      bool ok = child.level == n.level + 1;
      for (int a = 0; a < 3; ++a) ok = ok && child.cell[a] == 2 * n.cell[a] + ((octant >> a) & 1u);
      if (!ok) return r.fail("describes an inconsistent octree");
    }
    if (i == 0 && (n.cell[0] | n.cell[1] | n.cell[2]) != 0) {
      return r.fail("describes an inconsistent octree");
    }
  }
  for (ObjectId id : objects) {
    if (id >= expect.objects) return r.fail("names an object the scene does not have");
  }
  return {};
}

}  // namespace

Result<Octree> tryLoadOctree(const std::string& path, const FileExpectation& expect) {
  const Result<std::vector<unsigned char>> read = readWholeFile(path);
  if (!read) return read.status();
  const std::vector<unsigned char>& bytes = read.value();
  const Result<std::size_t> body = checkEnvelope(bytes, path);
  if (!body) return body.status();
  Reader r(bytes, body.value(), path);
  const Result<OctreeParams> params = readParams(r, expect);
  if (!params) return params.status();
  const OctreeParams& p = params.value();
  const auto node_count = r.get<std::uint64_t>();
  const auto object_count = r.get<std::uint64_t>();
  if (r.failed()) return r.status();
  constexpr std::size_t kNodeBytes = 6 * 4 + 3 * 4 + 4 * 4 + 2;
  const std::size_t per_face = maskBytesPerFace(p.regions);
  if (node_count == 0 || node_count > r.left() / kNodeBytes || object_count > r.left() / 4 ||
      r.left() != node_count * kNodeBytes + object_count * 4 + node_count * kFaces * per_face) {
    return r.fail("is truncated or has inconsistent sizes");
  }
  std::vector<OctreeNode> nodes = readNodes(r, node_count);
  std::vector<ObjectId> object_list(object_count);
  r.getBytes(object_list.data(), object_count * sizeof(ObjectId));
  if (r.failed()) return r.status();
  if (Status s = checkStructure(nodes, object_list, p, expect, r); !s) return s;
  Octree octree(p, std::move(nodes), std::move(object_list));
  for (std::uint64_t& m : octree.mutableMasks()) {
    m = 0;
    r.getBytes(&m, per_face);
  }
  if (r.failed()) return r.status();
  return octree;
}

}  // namespace logrid::ddo
