// Scenes from model files through assimp (see loader.hpp).
//
// The loader treats every file as hostile, because assimp 5.2 does not: small corruptions
// of ordinary files make it hang, abort or overflow its stack or heap (see the PLY and
// glTF sections and tests/fuzz/loader_fuzz_test.cpp). So the loader
//  * checks the file before assimp sees it (exists, regular, size limit), and lets only
//    the importers that claim the file's extension look at it;
//  * checks PLY files completely, and the JSON and node graph of glTF files, where assimp
//    is known to fail on malformed input;
//  * bounds what assimp may open besides the file (material libraries, buffers);
//  * checks assimp's raw output before its post-processing runs on it, and the result
//    after, since its own validation misses NaNs and empty faces;
//  * converts every exception into a logrid::Error.
#include "scene/loader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <new>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include "logrid/error.hpp"
#include "scene/camera_path.hpp"
#include "scene/scene.hpp"

#if defined(LOGRID_HAVE_ASSIMP) && LOGRID_HAVE_ASSIMP
#include <assimp/BaseImporter.h>
#include <assimp/DefaultIOSystem.h>
#include <assimp/material.h>
#include <assimp/matrix4x4.h>
#include <assimp/mesh.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>
#include <nlohmann/json.hpp>
#define LOGRID_LOADER_ASSIMP 1
#else
#define LOGRID_LOADER_ASSIMP 0
#endif

namespace logrid::samples {

#if LOGRID_LOADER_ASSIMP

namespace {

namespace fs = std::filesystem;

// Deeper node graphs than this are refused. Real files nest a few dozen levels; a
// deeper graph is almost certainly built to exhaust a recursive walker.
constexpr std::size_t kMaxNodeDepth = 1000;
// Mesh instances (= scene objects) and nodes visited. Each instance costs a 4x4 double
// matrix here and assimp already spent ~1 KiB per node, so these bound memory long
// before max_triangles would.
constexpr std::size_t kMaxInstances = std::size_t{1} << 20;
constexpr std::size_t kMaxNodes = std::size_t{1} << 22;

using DMat4 = aiMatrix4x4t<double>;

[[noreturn]] void fail(ErrorCode code, const std::string& path, const std::string& what) {
  throw Error(code, path + ": " + what);
}

std::string lowerCase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Everything that can be decided without parsing: the file exists, is a readable
// regular file, is not empty and not above the size limit. Doing this ourselves gives
// the user a precise message instead of assimp's generic "Unable to open file".
void checkFile(const std::string& path, const LoadOptions& options) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) {
    fail(ErrorCode::Environment, path,
         "no such file" + (ec ? " (" + ec.message() + ")" : std::string()));
  }
  if (fs::is_directory(status)) {
    fail(ErrorCode::Environment, path, "is a directory, not a model file");
  }
  if (!fs::is_regular_file(status)) {
    fail(ErrorCode::Environment, path, "is not a regular file (a device, pipe or socket?)");
  }
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec) fail(ErrorCode::Environment, path, "cannot read its size (" + ec.message() + ")");
  if (bytes > options.max_file_bytes) {
    std::ostringstream out;
    out << "is " << bytes << " bytes, more than the limit of " << options.max_file_bytes
        << " bytes (LoadOptions::max_file_bytes)";
    fail(ErrorCode::BadInput, path, out.str());
  }
  if (!std::ifstream(path, std::ios::binary)) {
    fail(ErrorCode::Environment, path, "cannot be opened for reading (permissions?)");
  }
  if (bytes == 0) fail(ErrorCode::BadInput, path, "is empty");
}

// Assimp opens more than the file it is given (OBJ material libraries, glTF buffers,
// ...), by names taken from the file. This refuses writes, non-regular files (a buffer
// named /dev/zero or a FIFO would hang the import) and files above the size limit.
class BoundedIOSystem : public Assimp::DefaultIOSystem {
 public:
  explicit BoundedIOSystem(std::uint64_t max_bytes) : max_bytes_(max_bytes) {}

  using Assimp::DefaultIOSystem::Open;
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (file == nullptr || mode == nullptr) return nullptr;
    if (std::string(mode).find_first_of("wa+") != std::string::npos) return nullptr;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec) || ec) return nullptr;
    const std::uintmax_t bytes = fs::file_size(file, ec);
    if (ec || bytes > max_bytes_) return nullptr;
    return Assimp::DefaultIOSystem::Open(file, mode);
  }

 private:
  std::uint64_t max_bytes_;
};

DMat4 toDouble(const aiMatrix4x4& m) {
  return DMat4(m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2,
               m.d3, m.d4);
}

DVec3 transformPoint(const DMat4& m, const aiVector3D& v) {
  const double x = v.x, y = v.y, z = v.z;
  return {m.a1 * x + m.a2 * y + m.a3 * z + m.a4, m.b1 * x + m.b2 * y + m.b3 * z + m.b4,
          m.c1 * x + m.c2 * y + m.c3 * z + m.c4};
}

bool isFinite(const DVec3& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

std::string meshLabel(const aiMesh& mesh, std::size_t index) {
  std::ostringstream out;
  out << "mesh " << index;
  if (mesh.mName.length > 0) out << " '" << mesh.mName.C_Str() << "'";
  return out.str();
}

std::string nodeLabel(const aiNode& node) {
  return node.mName.length > 0 ? "node '" + std::string(node.mName.C_Str()) + "'"
                               : std::string("an unnamed node");
}

// What the scene needs of one assimp mesh, computed once however often it is instanced:
// its triangles, and the vertices they use (unused vertices would only widen bounds and
// cost memory per instance).
struct MeshInfo {
  bool checked = false;
  std::vector<std::uint32_t> used;       // mesh vertex of each compacted vertex
  std::vector<std::uint32_t> triangles;  // compacted vertex indices, three per triangle
};

// Checks one mesh's arrays: pointers present, every face with at least one index, every
// index in range, every position finite. Runs on the importer's raw output, before
// assimp's post-processing: its validation step misses empty faces (it checks them only
// once primitive types are known) and NaNs, and the steps after it trust the data -- an
// empty face (a truncated ASCII PLY gave one, before checkPly) aborts the process in
// Triangulate's assertion, and NaN positions break the strict ordering that
// JoinIdenticalVertices sorts by. It runs again on the processed meshes as a guard for
// what the steps produce.
void checkMesh(const std::string& path, const aiMesh& mesh, std::size_t index) {
  const std::uint32_t vertices = mesh.mNumVertices;
  if (vertices > 0 && mesh.mVertices == nullptr) {
    fail(ErrorCode::BadInput, path, meshLabel(mesh, index) + " has no vertex positions");
  }
  if (mesh.mNumFaces > 0 && mesh.mFaces == nullptr) {
    fail(ErrorCode::BadInput, path, meshLabel(mesh, index) + " has no face array");
  }
  // A broken vertex makes the file broken even where no face uses it.
  for (std::uint32_t v = 0; v < vertices; ++v) {
    const aiVector3D& p = mesh.mVertices[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      std::ostringstream out;
      out << meshLabel(mesh, index) << ": vertex " << v << " is not finite (" << p.x << ", " << p.y
          << ", " << p.z << ")";
      fail(ErrorCode::BadInput, path, out.str());
    }
  }
  for (std::uint32_t f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    if (face.mNumIndices == 0 || face.mIndices == nullptr) {
      std::ostringstream out;
      out << meshLabel(mesh, index) << ": face " << f << " has no vertices (truncated file?)";
      fail(ErrorCode::BadInput, path, out.str());
    }
    for (unsigned k = 0; k < face.mNumIndices; ++k) {
      if (face.mIndices[k] >= vertices) {
        std::ostringstream out;
        out << meshLabel(mesh, index) << ": face " << f << " uses vertex " << face.mIndices[k]
            << " but the mesh has " << vertices << " vertices (truncated or corrupt file?)";
        fail(ErrorCode::BadInput, path, out.str());
      }
    }
  }
}

// Walks the node graph without recursion (a deep graph must not overflow our stack) and
// calls visit(node, accumulated transform) for each node, refusing graphs deeper than
// kMaxNodeDepth or larger than kMaxNodes. Transforms accumulate in double.
template <typename Visit>
void walkNodes(const std::string& path, const aiScene& ai, Visit&& visit) {
  struct Pending {
    const aiNode* node;
    DMat4 parent;
    std::size_t depth;
  };
  std::vector<Pending> stack{{ai.mRootNode, DMat4(), 0}};
  std::size_t nodes = 0;
  while (!stack.empty()) {
    const Pending item = stack.back();
    stack.pop_back();
    if (item.node == nullptr) fail(ErrorCode::BadInput, path, "the node graph has a null node");
    const aiNode& node = *item.node;
    if (item.depth > kMaxNodeDepth) {
      std::ostringstream out;
      out << "the node graph is deeper than " << kMaxNodeDepth << " levels (at " << nodeLabel(node)
          << ")";
      fail(ErrorCode::BadInput, path, out.str());
    }
    if (++nodes > kMaxNodes) {
      std::ostringstream out;
      out << "has more than " << kMaxNodes << " nodes";
      fail(ErrorCode::BadInput, path, out.str());
    }
    if (node.mNumMeshes > 0 && node.mMeshes == nullptr) {
      fail(ErrorCode::BadInput, path, nodeLabel(node) + " has no mesh list");
    }
    for (unsigned k = 0; k < node.mNumMeshes; ++k) {
      if (node.mMeshes[k] >= ai.mNumMeshes || ai.mMeshes[node.mMeshes[k]] == nullptr) {
        std::ostringstream out;
        out << nodeLabel(node) << " refers to mesh " << node.mMeshes[k] << " of " << ai.mNumMeshes;
        fail(ErrorCode::BadInput, path, out.str());
      }
    }
    if (node.mNumChildren > 0 && node.mChildren == nullptr) {
      fail(ErrorCode::BadInput, path, nodeLabel(node) + " has no child list");
    }
    const DMat4 transform = item.parent * toDouble(node.mTransformation);
    visit(node, transform);
    // Children pushed in reverse so objects come out in the file's order.
    for (unsigned c = node.mNumChildren; c-- > 0;) {
      stack.push_back({node.mChildren[c], transform, item.depth + 1});
    }
  }
}

// The importer's output, checked before assimp's post-processing steps run on it (see
// checkMesh). Also the place to tell a file without a single triangle apart from a
// broken one, with a clearer message than the post-processing would give.
void checkRawScene(const std::string& path, const aiScene& raw) {
  if (raw.mRootNode == nullptr) fail(ErrorCode::BadInput, path, "has no node graph");
  if (raw.mNumMeshes > 0 && raw.mMeshes == nullptr) {
    fail(ErrorCode::BadInput, path, "has no mesh array");
  }
  walkNodes(path, raw, [](const aiNode&, const DMat4&) {});
  bool has_triangles = false;
  for (std::uint32_t m = 0; m < raw.mNumMeshes; ++m) {
    if (raw.mMeshes[m] == nullptr) continue;  // reported when a node uses it
    const aiMesh& mesh = *raw.mMeshes[m];
    checkMesh(path, mesh, m);
    for (std::uint32_t f = 0; f < mesh.mNumFaces && !has_triangles; ++f) {
      has_triangles = mesh.mFaces[f].mNumIndices >= 3;
    }
  }
  if (!has_triangles) {
    fail(ErrorCode::BadInput, path,
         "has no triangles (no faces at all, or only points and lines, which are not loaded)");
  }
}

// Lists the mesh's triangles in `info`, over the vertices they use.
void prepareMesh(const std::string& path, const aiMesh& mesh, std::size_t index, MeshInfo& info) {
  info.checked = true;
  checkMesh(path, mesh, index);
  constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> remap(mesh.mNumVertices, kUnused);
  for (std::uint32_t f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    // Points and lines were dropped by SortByPType and polygons split by Triangulate;
    // anything else left over is not a triangle and has no area to occlude with.
    if (face.mNumIndices != 3) continue;
    for (unsigned k = 0; k < 3; ++k) {
      const std::uint32_t v = face.mIndices[k];
      if (remap[v] == kUnused) {
        remap[v] = static_cast<std::uint32_t>(info.used.size());
        info.used.push_back(v);
      }
      info.triangles.push_back(remap[v]);
    }
  }
}

struct Instance {
  std::uint32_t mesh = 0;
  const aiNode* node = nullptr;
  DMat4 transform;
};

// Lists every (node, mesh) pair that has triangles, with the node's accumulated
// transform. Enforces the instance and triangle limits as it goes, before any geometry
// is copied.
std::vector<Instance> collectInstances(const std::string& path, const aiScene& ai,
                                       const LoadOptions& options, std::vector<MeshInfo>& meshes) {
  std::vector<Instance> instances;
  std::uint64_t triangles = 0;
  std::uint64_t vertices = 0;
  walkNodes(path, ai, [&](const aiNode& node, const DMat4& transform) {
    for (unsigned k = 0; k < node.mNumMeshes; ++k) {
      const std::uint32_t m = node.mMeshes[k];
      MeshInfo& info = meshes[m];
      if (!info.checked) prepareMesh(path, *ai.mMeshes[m], m, info);
      if (info.triangles.empty()) continue;
      triangles += info.triangles.size() / 3;
      vertices += info.used.size();
      if (triangles > options.max_triangles) {
        std::ostringstream out;
        out << "has more than " << options.max_triangles
            << " triangles (LoadOptions::max_triangles)";
        fail(ErrorCode::BadInput, path, out.str());
      }
      // Scene indices and SceneObject ranges are 32-bit.
      if (triangles * 3 > std::numeric_limits<std::uint32_t>::max() ||
          vertices > std::numeric_limits<std::uint32_t>::max()) {
        fail(ErrorCode::BadInput, path, "has more vertices or indices than 32-bit indices allow");
      }
      if (instances.size() >= kMaxInstances) {
        std::ostringstream out;
        out << "has more than " << kMaxInstances << " mesh instances";
        fail(ErrorCode::BadInput, path, out.str());
      }
      instances.push_back({m, &node, transform});
    }
  });
  return instances;
}

std::uint32_t packColor(double r, double g, double b) {
  auto channel = [](double c) {
    if (!(c > 0.0)) return 0u;  // also NaN
    if (c >= 1.0) return 255u;
    return static_cast<std::uint32_t>(std::lround(c * 255.0));
  };
  return channel(r) | channel(g) << 8 | channel(b) << 16 | 0xFFu << 24;
}

// Hues a golden angle apart, so neighbouring objects differ clearly and the sequence
// never repeats; muted saturation and bright value keep it readable under shading.
std::uint32_t paletteColor(std::size_t object) {
  const double hue = std::fmod(0.61803398874989485 * static_cast<double>(object) + 0.1, 1.0);
  const double s = 0.55, v = 0.9;
  const double h6 = hue * 6.0;
  const int sector = static_cast<int>(h6) % 6;
  const double f = h6 - std::floor(h6);
  const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  switch (sector) {
    case 0: return packColor(v, t, p);
    case 1: return packColor(q, v, p);
    case 2: return packColor(p, v, t);
    case 3: return packColor(p, q, v);
    case 4: return packColor(t, p, v);
    default: return packColor(v, p, q);
  }
}

// The material's diffuse colour, opaque. Assimp gives meshes without a material its
// grey "DefaultMaterial" (OBJ without .mtl, PLY, STL); those, like materials without a
// diffuse colour, get a palette colour so objects stay distinguishable.
std::uint32_t objectColor(const aiScene& ai, const aiMesh& mesh, std::size_t object) {
  if (mesh.mMaterialIndex < ai.mNumMaterials && ai.mMaterials != nullptr &&
      ai.mMaterials[mesh.mMaterialIndex] != nullptr) {
    const aiMaterial& material = *ai.mMaterials[mesh.mMaterialIndex];
    aiString name;
    const bool is_default = material.Get(AI_MATKEY_NAME, name) == AI_SUCCESS &&
                            std::string(name.C_Str()) == AI_DEFAULT_MATERIAL_NAME;
    aiColor4D diffuse;
    if (!is_default && material.Get(AI_MATKEY_COLOR_DIFFUSE, diffuse) == AI_SUCCESS) {
      return packColor(diffuse.r, diffuse.g, diffuse.b);
    }
  }
  return paletteColor(object);
}

// Copies the instances into `scene`, positions relative to the centre of the model's
// bounds: a model placed far from its file's origin keeps small float coordinates, and
// the offset lives in Scene::origin in double.
void buildGeometry(const std::string& path, const aiScene& ai,
                   const std::vector<Instance>& instances, const std::vector<MeshInfo>& meshes,
                   Scene& scene) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  DVec3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  std::size_t vertex_total = 0, index_total = 0;
  for (const Instance& instance : instances) {
    const aiMesh& mesh = *ai.mMeshes[instance.mesh];
    const MeshInfo& info = meshes[instance.mesh];
    for (const std::uint32_t v : info.used) {
      const DVec3 p = transformPoint(instance.transform, mesh.mVertices[v]);
      if (!isFinite(p)) {
        std::ostringstream out;
        out << meshLabel(mesh, instance.mesh) << " under " << nodeLabel(*instance.node)
            << ": vertex " << v << " is not finite after the node's transform";
        fail(ErrorCode::BadInput, path, out.str());
      }
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    vertex_total += info.used.size();
    index_total += info.triangles.size();
  }
  const DVec3 centre{0.5 * lo.x + 0.5 * hi.x, 0.5 * lo.y + 0.5 * hi.y, 0.5 * lo.z + 0.5 * hi.z};
  // Relative to the centre every coordinate is at most half the extent; a model wider
  // than float's range cannot be stored (converting such a double to float is undefined).
  constexpr double kFloatMax = std::numeric_limits<float>::max();
  if (!(hi.x - centre.x <= kFloatMax && hi.y - centre.y <= kFloatMax &&
        hi.z - centre.z <= kFloatMax)) {
    fail(ErrorCode::BadInput, path, "the model is too large for float coordinates");
  }
  scene.origin = centre;
  scene.positions.reserve(vertex_total * 3);
  scene.indices.reserve(index_total);
  scene.objects.reserve(instances.size());
  for (const Instance& instance : instances) {
    const aiMesh& mesh = *ai.mMeshes[instance.mesh];
    const MeshInfo& info = meshes[instance.mesh];
    const auto base = static_cast<std::uint32_t>(scene.positions.size() / 3);
    for (const std::uint32_t v : info.used) {
      const DVec3 p = transformPoint(instance.transform, mesh.mVertices[v]);
      scene.positions.push_back(static_cast<float>(p.x - centre.x));
      scene.positions.push_back(static_cast<float>(p.y - centre.y));
      scene.positions.push_back(static_cast<float>(p.z - centre.z));
    }
    SceneObject object;
    object.first_index = static_cast<std::uint32_t>(scene.indices.size());
    object.index_count = static_cast<std::uint32_t>(info.triangles.size());
    object.color = objectColor(ai, mesh, scene.objects.size());
    for (const std::uint32_t i : info.triangles) scene.indices.push_back(base + i);
    scene.objects.push_back(object);
  }
}

// Clip planes and an orbit for the default walkthrough, from the bounds.
void frameScene(const std::string& path, Scene& scene) {
  const Aabb& b = scene.bounds;
  const double dx = double{b.max.x} - b.min.x, dy = double{b.max.y} - b.min.y,
               dz = double{b.max.z} - b.min.z;
  // The box's own centre (the local origin is only the centre up to float rounding).
  const DVec3 centre{scene.origin.x + 0.5 * (double{b.min.x} + b.max.x),
                     scene.origin.y + 0.5 * (double{b.min.y} + b.max.y),
                     scene.origin.z + 0.5 * (double{b.min.z} + b.max.z)};
  // A model of zero extent (one degenerate triangle) still needs a radius: one that
  // survives the addition to the centre in double, so no key's eye equals its target.
  const double magnitude =
      std::max({1.0, std::abs(centre.x), std::abs(centre.y), std::abs(centre.z)});
  const double radius = std::max(0.5 * std::sqrt(dx * dx + dy * dy + dz * dz), 1e-9 * magnitude);

  // The orbit runs at 1.2 radii from the centre, so every point of the model is at least
  // 0.2 radii and at most 2.2 radii from the eye. The far plane covers that with a margin
  // (and covers a camera anywhere inside the bounds, at most 2 radii from any point). The
  // near plane is the far plane / 10^4 -- not the larger 0.2 radii the orbit would allow,
  // so a user path that flies into the model is not clipped -- which keeps a 24-bit depth
  // buffer's resolution at the far plane near 10^-3 radii.
  scene.far_plane = 2.75 * radius;
  scene.near_plane = scene.far_plane * 1e-4;

  constexpr double kPi = 3.14159265358979323846;
  constexpr int kKeys = 12;
  const double height = 0.3 * radius;  // slightly above: the model is seen from above
  const double across = std::sqrt(1.2 * 1.2 - 0.3 * 0.3) * radius;
  std::vector<CameraKey> keys;
  for (int k = 0; k <= kKeys; ++k) {  // the last key closes the loop
    const double angle = 2.0 * kPi * (k % kKeys) / kKeys;
    CameraKey key;
    key.position = {centre.x + across * std::cos(angle), centre.y + height,
                    centre.z + across * std::sin(angle)};
    key.look_at = centre;
    keys.push_back(key);
  }
  try {
    scene.path = CameraPath(std::move(keys));
  } catch (const Error& e) {
    fail(ErrorCode::BadInput, path, std::string("cannot build a camera path: ") + e.what());
  }
}

// Leaves registered only the importers that claim the file's extension, and refuses
// files that no importer claims. When several importers claim an extension (.gltf,
// .glb, .xml, ...) and none accepts the content, assimp would otherwise try every
// importer it has on it by signature: a file named .gltf could reach any of ~50
// parsers, some with known hangs (a .gltf holding a PLY header without end_header
// loops forever). The match is on the end of the name, as assimp does, so
// double extensions such as .mesh.xml keep their importer.
void restrictImporters(const std::string& path, Assimp::Importer& importer) {
  const std::string name = lowerCase(fs::path(path).filename().string());
  auto claims = [&](Assimp::BaseImporter& candidate) {
    std::set<std::string> extensions;
    candidate.GetExtensionList(extensions);
    for (const std::string& extension : extensions) {
      const std::string suffix = "." + lowerCase(extension);
      if (name.size() > suffix.size() &&
          name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
        return true;
      }
    }
    return false;
  };
  std::vector<Assimp::BaseImporter*> others;
  bool claimed = false;
  for (std::size_t i = 0; i < importer.GetImporterCount(); ++i) {
    Assimp::BaseImporter* candidate = importer.GetImporter(i);
    if (candidate == nullptr) continue;
    if (claims(*candidate)) {
      claimed = true;
    } else {
      others.push_back(candidate);
    }
  }
  if (!claimed) {
    std::string known;
    importer.GetExtensionList(known);
    const std::string extension = fs::path(path).extension().string();
    fail(ErrorCode::BadInput, path,
         (extension.empty() ? std::string("has no file extension")
                            : "has an unknown extension '" + extension + "'") +
             "; cannot tell its format (assimp reads " + known + ")");
  }
  for (Assimp::BaseImporter* other : others) {
    // UnregisterLoader hands ownership back to the caller.
    if (importer.UnregisterLoader(other) == AI_SUCCESS) delete other;
  }
}

// --- PLY -------------------------------------------------------------------------------
//
// Assimp 5.2's PLY importer trusts its input, and small corruptions make it hang, abort
// or corrupt the heap (found by tests/fuzz/loader_fuzz_test.cpp):
//  * a header without an "end_header" line, or with a NUL, form feed or lone CR in it,
//    sends its line reader into an endless loop or past the end of its buffer;
//  * an element declared twice overflows a heap buffer (assimp issue 5729);
//  * element and list counts are believed: "element face 4294967295" loops that often
//    at the end of the file, and a list count of 2147483647 in a data line allocates
//    16 GiB before the parser notices that the line is short;
//  * a comment between an element's properties drops the properties after it, and
//    binary data starting with byte 0x0A, or after a CR LF header, is read one byte off
//    (both silently give wrong geometry, or desynchronise the counts above).
// So a PLY file is checked here, strictly, before assimp sees it: a well-formed header,
// and a body that holds what the header declares, every list count included. Assimp then
// only reads well-formed files. The checks split lines and tokens as assimp does and
// refuse whatever the two could read differently (blank or very long lines, numbers
// that assimp would read only in part).

struct PlyProperty {
  std::string name;
  bool list = false;
  char count_kind = 'u';  // of the list count: 'i' signed or 'u' unsigned integer
  int count_size = 0;     // bytes
  char kind = 'f';        // 'i', 'u' or 'f' (floating point)
  int size = 0;           // bytes
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::uint64_t data_offset = 0;  // first byte after the end_header line
};

// The type names assimp knows.
bool plyType(const std::string& name, char& kind, int& size) {
  static const struct {
    const char* name;
    char kind;
    int size;
  } kTypes[] = {{"char", 'i', 1},  {"int8", 'i', 1},    {"uchar", 'u', 1},  {"uint8", 'u', 1},
                {"short", 'i', 2}, {"int16", 'i', 2},   {"ushort", 'u', 2}, {"uint16", 'u', 2},
                {"int", 'i', 4},   {"int32", 'i', 4},   {"uint", 'u', 4},   {"uint32", 'u', 4},
                {"float", 'f', 4}, {"float32", 'f', 4}, {"double", 'f', 8}, {"float64", 'f', 8}};
  for (const auto& type : kTypes) {
    if (name == type.name) {
      kind = type.kind;
      size = type.size;
      return true;
    }
  }
  return false;
}

// Words separated by spaces and tabs, the only blanks assimp skips.
std::vector<std::string> plyWords(const std::string& line) {
  std::vector<std::string> words;
  const char* const blanks = " \t";
  for (std::size_t w = line.find_first_not_of(blanks); w != std::string::npos;) {
    const std::size_t end = std::min(line.find_first_of(blanks, w), line.size());
    words.push_back(line.substr(w, end - w));
    w = line.find_first_not_of(blanks, end);
  }
  return words;
}

bool isDigits(const std::string& s, std::size_t from = 0) {
  return s.size() > from && s.find_first_not_of("0123456789", from) == std::string::npos;
}

// The decimal value of a string of digits, saturated at 2^64 - 1.
std::uint64_t digitsValue(const std::string& s, std::size_t from = 0) {
  constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t value = 0;
  for (std::size_t i = from; i < s.size(); ++i) {
    value = value > (kMax - 9) / 10 ? kMax : value * 10 + std::uint64_t(s[i] - '0');
  }
  return value;
}

bool isPrintable(char c) { return c >= 0x20 && c <= 0x7E; }

// A number of the type, written so that assimp's parser (strtoul10, strtol10,
// fast_atoreal_move) reads all of it: unsigned "123", signed "-123", floating point
// "-1.5e-3" (no "1.", no "nan"). Integers must fit 32 bits.
bool plyNumber(const std::string& word, char kind) {
  if (word.empty()) return false;
  if (kind == 'u') return isDigits(word) && digitsValue(word) <= 0xFFFFFFFFu;
  const std::size_t sign = (word[0] == '-' || word[0] == '+') ? 1 : 0;
  if (kind == 'i') return isDigits(word, sign) && digitsValue(word, sign) <= 0x80000000u;
  std::size_t i = sign;
  const std::size_t mantissa = word.find_first_not_of("0123456789", i);
  bool digits = mantissa != i;
  i = mantissa;
  if (i < word.size() && word[i] == '.') {
    const std::size_t fraction = word.find_first_not_of("0123456789", i + 1);
    if (fraction == i + 1) return false;  // "1." or ".": assimp leaves the '.' unread
    digits = true;
    i = fraction;
  }
  if (!digits) return false;
  if (i < word.size() && (word[i] == 'e' || word[i] == 'E')) {
    const std::size_t exponent =
        (i + 1 < word.size() && (word[i + 1] == '-' || word[i + 1] == '+')) ? i + 2 : i + 1;
    const std::size_t end = word.find_first_not_of("0123456789", exponent);
    if (end == exponent) return false;
    i = end;
  }
  return i == std::string::npos || i == word.size();
}

[[noreturn]] void plyFail(const std::string& path, const std::string& what) {
  fail(ErrorCode::BadInput, path, "is not a well-formed PLY file: " + what);
}

// Reads and checks the header.
void readPlyHeader(const std::string& path, PlyHeader& header) {
  constexpr std::size_t kScanBytes = std::size_t{1} << 20;
  std::ifstream in(path, std::ios::binary);
  std::string head(kScanBytes, '\0');
  in.read(&head[0], static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));

  bool have_format = false, comment_in_element = false, has_cr = false;
  std::size_t begin = 0;
  for (int number = 1;; ++number) {
    const std::size_t end = head.find('\n', begin);
    if (end == std::string::npos) {
      plyFail(path, "the header has no end_header line in the first 1 MiB (truncated?)");
    }
    std::string line = head.substr(begin, end - begin);
    begin = end + 1;
    if (!line.empty() && line.back() == '\r') {
      line.pop_back();
      has_cr = true;
    }
    const std::string where = "header line " + std::to_string(number);
    for (const char c : line) {
      if (!isPrintable(c) && c != '\t') {
        plyFail(path, where + " holds a control or non-ASCII byte");
      }
    }
    const std::vector<std::string> w = plyWords(line);
    if (number == 1) {
      if (w.size() != 1 || lowerCase(w[0]) != "ply") plyFail(path, "the first line is not 'ply'");
      continue;
    }
    if (w.empty()) plyFail(path, where + " is blank");
    if (w[0] == "comment" || w[0] == "obj_info") {
      comment_in_element = !header.elements.empty();
      continue;
    }
    if (w[0] == "end_header" && w.size() == 1) {
      header.data_offset = begin;
      break;
    }
    if (w[0] == "format" && w.size() == 3 && !have_format && header.elements.empty()) {
      if (w[1] == "ascii") {
        header.format = PlyFormat::Ascii;
      } else if (w[1] == "binary_little_endian") {
        header.format = PlyFormat::BinaryLittleEndian;
      } else if (w[1] == "binary_big_endian") {
        header.format = PlyFormat::BinaryBigEndian;
      } else {
        plyFail(path, where + ": unknown format '" + w[1] + "'");
      }
      have_format = true;
      continue;
    }
    if (w[0] == "element" && w.size() == 3 && have_format) {
      if (!isDigits(w[2]) || digitsValue(w[2]) > 0xFFFFFFFFu) {
        plyFail(path, where + ": element count '" + w[2] + "' is not a 32-bit count");
      }
      for (const PlyElement& other : header.elements) {
        if (other.name == w[1]) plyFail(path, where + ": element '" + w[1] + "' declared twice");
      }
      header.elements.push_back({w[1], digitsValue(w[2]), {}});
      comment_in_element = false;
      continue;
    }
    if (w[0] == "property" && !header.elements.empty()) {
      PlyElement& element = header.elements.back();
      if (comment_in_element) {
        plyFail(path, where + ": a comment between the properties of element '" + element.name +
                          "' (assimp 5.2 drops the properties after it)");
      }
      PlyProperty property;
      bool ok = false;
      if (w.size() == 3) {
        ok = plyType(w[1], property.kind, property.size);
      } else if (w.size() == 5 && w[1] == "list") {
        property.list = true;
        ok = plyType(w[2], property.count_kind, property.count_size) &&
             property.count_kind != 'f' && plyType(w[3], property.kind, property.size);
      }
      if (!ok) plyFail(path, where + ": malformed property '" + line + "'");
      property.name = w.back();
      for (const PlyProperty& other : element.properties) {
        if (other.name == property.name) {
          plyFail(path, where + ": property '" + property.name + "' declared twice");
        }
      }
      element.properties.push_back(property);
      continue;
    }
    plyFail(path, where + ": unexpected '" + line + "'");
  }
  if (!have_format) plyFail(path, "the header has no format line");
  if (has_cr && header.format != PlyFormat::Ascii) {
    plyFail(path,
            "a binary PLY header with CR LF line ends (assimp 5.2 reads the data after it "
            "one byte off)");
  }
}

// ASCII: one instance per line, each property's values as words of the line, and list
// counts equal to the values that follow. Lines are checked for what assimp's line reader
// mishandles: control bytes, blank lines, and lines over 64 KiB.
void checkPlyAscii(const std::string& path, const PlyHeader& header) {
  constexpr std::size_t kMaxLine = std::size_t{1} << 16;
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(header.data_offset));
  std::string line;
  std::uint64_t number = 0;
  auto nextLine = [&]() {
    if (!std::getline(in, line)) return false;
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.size() > kMaxLine) {
      plyFail(path, "data line " + std::to_string(number) + " is longer than 64 KiB");
    }
    for (const char c : line) {
      if (!isPrintable(c) && c != '\t') {
        plyFail(path, "data line " + std::to_string(number) + " holds a control or non-ASCII byte");
      }
    }
    return true;
  };
  for (const PlyElement& element : header.elements) {
    for (std::uint64_t i = 0; i < element.count; ++i) {
      if (!nextLine()) {
        std::ostringstream out;
        out << "the file ends after " << i << " of " << element.count << " '" << element.name
            << "' lines (truncated?)";
        plyFail(path, out.str());
      }
      const std::vector<std::string> w = plyWords(line);
      const std::string where = "data line " + std::to_string(number) + " ('" + element.name + "')";
      if (w.empty()) plyFail(path, where + " is blank");
      std::size_t next = 0;
      for (const PlyProperty& property : element.properties) {
        std::uint64_t values = 1;
        if (property.list) {
          const std::uint64_t max = property.count_kind == 'u'
                                        ? (std::uint64_t{1} << (8 * property.count_size)) - 1
                                        : (std::uint64_t{1} << (8 * property.count_size - 1)) - 1;
          if (next >= w.size() || !isDigits(w[next]) || digitsValue(w[next]) > max) {
            plyFail(path, where + ": bad list count for '" + property.name + "'");
          }
          values = digitsValue(w[next++]);
          if (values > w.size() - next) {
            std::ostringstream out;
            out << where << ": list '" << property.name << "' declares " << values
                << " values but the line has " << w.size() - next;
            plyFail(path, out.str());
          }
        }
        for (std::uint64_t v = 0; v < values; ++v, ++next) {
          if (next >= w.size()) plyFail(path, where + ": too few values");
          if (!plyNumber(w[next], property.kind)) {
            plyFail(path, where + ": '" + w[next] + "' is not a " +
                              (property.kind == 'f' ? "finite number" : "32-bit integer"));
          }
        }
      }
      if (next != w.size()) plyFail(path, where + ": more values than the header declares");
    }
  }
  while (nextLine()) {
    if (!plyWords(line).empty()) plyFail(path, "data after the last element");
  }
}

// Binary: the declared instances fit in the file, every list count included.
void checkPlyBinary(const std::string& path, const PlyHeader& header) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(header.data_offset));
  std::vector<unsigned char> buffer(std::size_t{1} << 16);
  std::size_t have = 0, at = 0;               // bytes in buffer, read position in it
  std::uint64_t offset = header.data_offset;  // file offset of buffer[at]
  auto available = [&](std::size_t bytes) {   // makes `bytes` bytes available at `at`
    if (have - at >= bytes) return true;
    std::copy(buffer.begin() + static_cast<std::ptrdiff_t>(at),
              buffer.begin() + static_cast<std::ptrdiff_t>(have), buffer.begin());
    have -= at;
    at = 0;
    in.read(reinterpret_cast<char*>(buffer.data() + have),
            static_cast<std::streamsize>(buffer.size() - have));
    have += static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0));
    return have >= bytes;
  };
  auto skip = [&](std::uint64_t bytes) {
    const std::uint64_t in_buffer = std::min<std::uint64_t>(bytes, have - at);
    at += static_cast<std::size_t>(in_buffer);
    offset += bytes;
    if (bytes > in_buffer) {
      at = have = 0;
      in.clear();
      in.seekg(static_cast<std::streamoff>(offset));
    }
  };
  std::error_code ec;
  const std::uintmax_t file_bytes = fs::file_size(path, ec);
  if (ec) fail(ErrorCode::Environment, path, "cannot read its size (" + ec.message() + ")");
  if (file_bytes > header.data_offset && available(1) && buffer[at] == '\n') {
    plyFail(path, "binary data starting with byte 0x0A (assimp 5.2 reads it one byte off)");
  }
  auto truncated = [&](const PlyElement& element, std::uint64_t i) {
    std::ostringstream out;
    out << "the file ends in '" << element.name << "' " << i << " of " << element.count
        << " (truncated, or a corrupt list count)";
    plyFail(path, out.str());
  };
  const bool big_endian = header.format == PlyFormat::BinaryBigEndian;
  for (const PlyElement& element : header.elements) {
    // Without lists every instance has the same size: check them all at once.
    std::uint64_t fixed_size = 0;
    for (const PlyProperty& property : element.properties) {
      fixed_size = property.list ? 0 : fixed_size + std::uint64_t(property.size);
      if (property.list) break;
    }
    if (fixed_size > 0) {
      const std::uint64_t left = file_bytes - std::min<std::uint64_t>(offset, file_bytes);
      if (element.count > left / fixed_size) truncated(element, left / fixed_size);
      skip(element.count * fixed_size);
      continue;
    }
    for (std::uint64_t i = 0; i < element.count; ++i) {
      for (const PlyProperty& property : element.properties) {
        std::uint64_t values = 1;
        if (property.list) {
          const std::size_t n = static_cast<std::size_t>(property.count_size);
          if (offset + n > file_bytes || !available(n)) truncated(element, i);
          std::uint64_t count = 0;
          for (std::size_t b = 0; b < n; ++b) {
            count |= std::uint64_t{buffer[at + (big_endian ? n - 1 - b : b)]} << (8 * b);
          }
          if (property.count_kind == 'i' && (count >> (8 * n - 1)) != 0) {
            plyFail(path, "a negative list count for '" + property.name + "'");
          }
          skip(n);
          values = count;
        }
        const std::uint64_t bytes = values * std::uint64_t(property.size);
        if (bytes > file_bytes - std::min<std::uint64_t>(offset, file_bytes)) {
          truncated(element, i);
        }
        skip(bytes);
      }
    }
  }
}

// See the section's comment. Only files named .ply reach assimp's PLY importer (see
// restrictImporters), and those must be well-formed PLY, starting with the line "ply"
// (assimp also takes a file that starts with blank lines, and then loops for ever when
// its header has no end).
void checkPly(const std::string& path) {
  if (lowerCase(fs::path(path).extension().string()) != ".ply") return;
  PlyHeader header;
  readPlyHeader(path, header);
  // Every instance takes at least a line or a byte: refuse absurd counts before walking.
  std::error_code ec;
  const std::uintmax_t bytes = fs::file_size(path, ec);
  const std::uint64_t data = ec || bytes <= header.data_offset ? 0 : bytes - header.data_offset;
  std::uint64_t instances = 0;
  // No overflow: counts are 32-bit, and a 1 MiB header has fewer than 2^17 elements.
  for (const PlyElement& element : header.elements) instances += element.count;
  if (instances > data) {
    std::ostringstream out;
    out << "the header declares " << instances << " element instances but only " << data
        << " bytes follow it (truncated?)";
    plyFail(path, out.str());
  }
  if (header.format == PlyFormat::Ascii) {
    checkPlyAscii(path, header);
  } else {
    checkPlyBinary(path, header);
  }
}

// --- glTF ------------------------------------------------------------------------------
//
// Assimp 5.2 parses glTF JSON with rapidjson's recursive parser and imports the node
// graph recursively, copying every node as often as it is used: a .gltf of 200000 nested
// '[' or a chain of 50000 nodes overflows the stack (a crash), and nodes that each use
// the next one twice expand to 2^depth copies (memory until the machine gives out). So
// the JSON of a glTF file is checked first: its nesting depth, then the depth of its
// node graph and the number of nodes it expands to.

constexpr int kMaxJsonDepth = 128;

// The JSON of a .gltf file, or the JSON chunk of a .glb after checking the .glb's
// framing: assimp allocates whatever a chunk header declares before it reads the chunk,
// so a JSON chunk declared 2 GiB long in a 1 KiB file costs 2 GiB and seconds.
std::string gltfJson(const std::string& path, const std::string& extension) {
  std::ifstream in(path, std::ios::binary);
  if (extension == ".gltf") {
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  std::error_code ec;
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec) fail(ErrorCode::Environment, path, "cannot read its size (" + ec.message() + ")");
  auto bad = [&](const std::string& what) {
    fail(ErrorCode::BadInput, path, "is not a well-formed binary glTF file: " + what);
  };
  // Magic "glTF", version, total length, then (glTF 2) the JSON chunk's length and type
  // "JSON", or (glTF 1) the JSON content's length and format 0.
  unsigned char header[28] = {};
  in.read(reinterpret_cast<char*>(header), sizeof header);
  auto word = [&](std::size_t at) {
    return std::uint32_t{header[at]} | std::uint32_t{header[at + 1]} << 8 |
           std::uint32_t{header[at + 2]} << 16 | std::uint32_t{header[at + 3]} << 24;
  };
  if (bytes < 20 || std::string(reinterpret_cast<const char*>(header), 4) != "glTF") {
    bad("no glTF header");
  }
  const std::uint32_t version = word(4), length = word(8), json_length = word(12);
  if (version != 1 && version != 2) bad("version " + std::to_string(version));
  if (length > bytes || length < 20) {
    std::ostringstream out;
    out << "its header declares " << length << " bytes, the file has " << bytes << " (truncated?)";
    bad(out.str());
  }
  if (json_length > length - 20) {
    std::ostringstream out;
    out << "a JSON chunk of " << json_length << " bytes in a file of " << length;
    bad(out.str());
  }
  if (version == 2) {
    if (std::string(reinterpret_cast<const char*>(header) + 16, 4) != "JSON") {
      bad("the first chunk is not JSON");
    }
    // The binary chunk, if any, must fit too.
    const std::uint64_t bin_at = 20 + std::uint64_t{json_length};
    if (bin_at + 8 <= length) {
      unsigned char chunk[4] = {};
      in.seekg(static_cast<std::streamoff>(bin_at));
      in.read(reinterpret_cast<char*>(chunk), 4);
      const std::uint32_t bin_length = std::uint32_t{chunk[0]} | std::uint32_t{chunk[1]} << 8 |
                                       std::uint32_t{chunk[2]} << 16 |
                                       std::uint32_t{chunk[3]} << 24;
      if (bin_length > length - bin_at - 8) {
        std::ostringstream out;
        out << "a binary chunk of " << bin_length << " bytes with " << length - bin_at - 8
            << " left in the file";
        bad(out.str());
      }
    }
  }
  std::string json(json_length, '\0');
  in.clear();
  in.seekg(20);
  in.read(&json[0], static_cast<std::streamsize>(json_length));
  return json;
}

void checkGltf(const std::string& path) {
  const std::string extension = lowerCase(fs::path(path).extension().string());
  if (extension != ".gltf" && extension != ".glb") return;
  const std::string json = gltfJson(path, extension);

  // Nesting depth, outside strings.
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < json.size(); ++i) {
    const char c = json[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) {
        std::ostringstream out;
        out << "its JSON nests deeper than " << kMaxJsonDepth << " levels";
        fail(ErrorCode::BadInput, path, out.str());
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }

  // The node graph: glTF 2 lists nodes in an array and children by index, glTF 1 in an
  // object and children by name. Anything malformed is left for assimp to report.
  const nlohmann::json document = nlohmann::json::parse(json, nullptr, false);
  if (!document.is_object() || !document.contains("nodes")) return;
  const nlohmann::json& nodes = document["nodes"];
  std::vector<const nlohmann::json*> node_list;
  std::unordered_map<std::string, std::size_t> names;
  if (nodes.is_array()) {
    for (const nlohmann::json& node : nodes) node_list.push_back(&node);
  } else if (nodes.is_object()) {
    for (auto it = nodes.begin(); it != nodes.end(); ++it) {
      names.emplace(it.key(), node_list.size());
      node_list.push_back(&it.value());
    }
  } else {
    return;
  }
  const std::size_t count = node_list.size();
  std::vector<std::vector<std::size_t>> children(count);
  for (std::size_t n = 0; n < count; ++n) {
    if (!node_list[n]->is_object() || !node_list[n]->contains("children")) continue;
    const nlohmann::json& list = (*node_list[n])["children"];
    if (!list.is_array()) continue;
    for (const nlohmann::json& child : list) {
      if (child.is_number_unsigned() && child.get<std::uint64_t>() < count) {
        children[n].push_back(static_cast<std::size_t>(child.get<std::uint64_t>()));
      } else if (child.is_string()) {
        const auto it = names.find(child.get<std::string>());
        if (it != names.end()) children[n].push_back(it->second);
      }
    }
  }
  // Per node, the depth of its subtree and the number of nodes it expands to
  // (saturating), by an iterative depth-first walk.
  std::vector<std::uint64_t> expanded(count, 0), height(count, 0);
  std::vector<char> state(count, 0);  // 0 new, 1 on the stack, 2 done
  for (std::size_t root = 0; root < count; ++root) {
    if (state[root] != 0) continue;
    std::vector<std::pair<std::size_t, std::size_t>> stack{{root, 0}};  // node, next child
    state[root] = 1;
    while (!stack.empty()) {
      auto& [node, next] = stack.back();
      if (next < children[node].size()) {
        const std::size_t child = children[node][next++];
        if (state[child] == 1) fail(ErrorCode::BadInput, path, "the node graph has a cycle");
        if (state[child] == 0) {
          state[child] = 1;
          stack.push_back({child, 0});
        }
        continue;
      }
      std::uint64_t total = 1, deepest = 0;
      for (const std::size_t child : children[node]) {
        total = std::min<std::uint64_t>(total + expanded[child], std::uint64_t{1} << 62);
        deepest = std::max(deepest, height[child]);
      }
      expanded[node] = total;
      height[node] = deepest + 1;
      state[node] = 2;
      if (height[node] > kMaxNodeDepth) {
        std::ostringstream out;
        out << "the node graph is deeper than " << kMaxNodeDepth << " levels";
        fail(ErrorCode::BadInput, path, out.str());
      }
      if (total > kMaxInstances) {
        std::ostringstream out;
        out << "the node graph expands to more than " << kMaxInstances
            << " nodes (nodes used by several parents are copied for each)";
        fail(ErrorCode::BadInput, path, out.str());
      }
      stack.pop_back();
    }
  }
}

Scene loadWithAssimp(const std::string& path, const LoadOptions& options) {
  checkFile(path, options);

  Assimp::Importer importer;
  restrictImporters(path, importer);
  checkPly(path);
  checkGltf(path);
  importer.SetIOHandler(new BoundedIOSystem(options.max_file_bytes));
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  auto assimpFailed = [&]() {
    const std::string error = importer.GetErrorString();
    fail(ErrorCode::BadInput, path, error.empty() ? "assimp cannot read it" : error);
  };
  // Parse only, check what the importer made (checkRawScene), then post-process.
  const aiScene* raw = importer.ReadFile(path, 0);
  if (raw == nullptr) assimpFailed();
  checkRawScene(path, *raw);
  const aiScene* ai =
      importer.ApplyPostProcessing(aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                                   aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (ai == nullptr) assimpFailed();
  if (ai->mRootNode == nullptr || (ai->mNumMeshes > 0 && ai->mMeshes == nullptr)) {
    fail(ErrorCode::BadInput, path, "has no triangles after assimp's post-processing");
  }

  std::vector<MeshInfo> meshes(ai->mNumMeshes);
  const std::vector<Instance> instances = collectInstances(path, *ai, options, meshes);
  if (instances.empty()) {
    fail(ErrorCode::BadInput, path, "has no triangles (points and lines are not loaded)");
  }

  Scene scene;
  scene.name = fs::path(path).stem().string();
  buildGeometry(path, *ai, instances, meshes, scene);
  computeBounds(scene);
  frameScene(path, scene);
  try {
    validateScene(scene);
  } catch (const Error& e) {
    fail(e.code(), path, e.what());
  }
  return scene;
}

}  // namespace

Scene loadSceneFile(const std::string& path, const LoadOptions& options) {
  // Assimp reports most failures through its error string, but it can also throw (its
  // DeadlyImportError from post-processing, std::bad_alloc for a forged element count,
  // std::length_error, ...); nothing but logrid::Error may leave this function.
  try {
    return loadWithAssimp(path, options);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail(ErrorCode::BadInput, path,
         "out of memory while loading (a malformed size in the file, or a model too large "
         "for this machine)");
  } catch (const std::exception& e) {
    fail(ErrorCode::BadInput, path, std::string("cannot be read: ") + e.what());
  } catch (...) {
    fail(ErrorCode::BadInput, path, "cannot be read: unknown exception from assimp");
  }
}

bool sceneFilesSupported() { return true; }

#else  // no assimp

Scene loadSceneFile(const std::string& path, const LoadOptions& /*options*/) {
  throw Error(ErrorCode::Unsupported,
              path +
                  ": this build cannot load model files; install libassimp-dev and rebuild "
                  "with -DLOGRID_WITH_ASSIMP=ON");
}

bool sceneFilesSupported() { return false; }

#endif

}  // namespace logrid::samples
