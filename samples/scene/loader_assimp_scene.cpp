// What assimp made, checked and turned into a Scene (loader_detail.hpp). Transforms are
// accumulated and applied in double precision with GLM.
#include <assimp/material.h>
#include <assimp/mesh.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <glm/ext/matrix_double4x4.hpp>
#include <glm/ext/vector_double3.hpp>
#include <glm/ext/vector_double4.hpp>

#include "logrid/error.hpp"
#include "scene/camera_path.hpp"
#include "scene/loader_detail.hpp"
#include "scene/scene.hpp"

namespace logrid::samples::load {
namespace {

// assimp's matrices are row-major (a1..a4 is the first row), GLM's column-major.
glm::dmat4 toDouble(const aiMatrix4x4& m) {
  return glm::dmat4(m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4,
                    m.b4, m.c4, m.d4);
}

glm::dvec3 transformPoint(const glm::dmat4& m, const aiVector3D& v) {
  return glm::dvec3(m * glm::dvec4(v.x, v.y, v.z, 1.0));
}

bool isFinite(const glm::dvec3& p) {
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
    glm::dmat4 parent;
    std::size_t depth;
  };
  std::vector<Pending> stack{{ai.mRootNode, glm::dmat4(1.0), 0}};
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
    const glm::dmat4 transform = item.parent * toDouble(node.mTransformation);
    visit(node, transform);
    // Children pushed in reverse so objects come out in the file's order.
    for (unsigned c = node.mNumChildren; c-- > 0;) {
      stack.push_back({node.mChildren[c], transform, item.depth + 1});
    }
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
  glm::dmat4 transform{1.0};
};

// Lists every (node, mesh) pair that has triangles, with the node's accumulated
// transform. Enforces the instance and triangle limits as it goes, before any geometry
// is copied.
std::vector<Instance> collectInstances(const std::string& path, const aiScene& ai,
                                       const LoadOptions& options, std::vector<MeshInfo>& meshes) {
  std::vector<Instance> instances;
  std::uint64_t triangles = 0;
  std::uint64_t vertices = 0;
  walkNodes(path, ai, [&](const aiNode& node, const glm::dmat4& transform) {
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
  glm::dvec3 lo(inf), hi(-inf);
  std::size_t vertex_total = 0, index_total = 0;
  for (const Instance& instance : instances) {
    const aiMesh& mesh = *ai.mMeshes[instance.mesh];
    const MeshInfo& info = meshes[instance.mesh];
    for (const std::uint32_t v : info.used) {
      const glm::dvec3 p = transformPoint(instance.transform, mesh.mVertices[v]);
      if (!isFinite(p)) {
        std::ostringstream out;
        out << meshLabel(mesh, instance.mesh) << " under " << nodeLabel(*instance.node)
            << ": vertex " << v << " is not finite after the node's transform";
        fail(ErrorCode::BadInput, path, out.str());
      }
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    vertex_total += info.used.size();
    index_total += info.triangles.size();
  }
  // 0.5 lo + 0.5 hi rather than (lo + hi) / 2, which could overflow.
  const glm::dvec3 centre = 0.5 * lo + 0.5 * hi;
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
      const glm::dvec3 p = transformPoint(instance.transform, mesh.mVertices[v]) - centre;
      scene.positions.push_back(static_cast<float>(p.x));
      scene.positions.push_back(static_cast<float>(p.y));
      scene.positions.push_back(static_cast<float>(p.z));
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
  const glm::dvec3 centre =
      scene.origin + 0.5 * glm::dvec3(double{b.min.x} + b.max.x, double{b.min.y} + b.max.y,
                                      double{b.min.z} + b.max.z);
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
    key.position = centre + glm::dvec3(across * std::cos(angle), height, across * std::sin(angle));
    key.look_at = centre;
    keys.push_back(key);
  }
  try {
    scene.path = CameraPath(std::move(keys));
  } catch (const Error& e) {
    fail(ErrorCode::BadInput, path, std::string("cannot build a camera path: ") + e.what());
  }
}

}  // namespace

// The importer's output, checked before assimp's post-processing steps run on it (see
// checkMesh). Also the place to tell a file without a single triangle apart from a
// broken one, with a clearer message than the post-processing would give.
void checkRawScene(const std::string& path, const aiScene& raw) {
  if (raw.mRootNode == nullptr) fail(ErrorCode::BadInput, path, "has no node graph");
  if (raw.mNumMeshes > 0 && raw.mMeshes == nullptr) {
    fail(ErrorCode::BadInput, path, "has no mesh array");
  }
  walkNodes(path, raw, [](const aiNode&, const glm::dmat4&) {});
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

Scene sceneFromAssimp(const std::string& path, const aiScene& ai, const LoadOptions& options) {
  if (ai.mRootNode == nullptr || (ai.mNumMeshes > 0 && ai.mMeshes == nullptr)) {
    fail(ErrorCode::BadInput, path, "has no triangles after assimp's post-processing");
  }
  std::vector<MeshInfo> meshes(ai.mNumMeshes);
  const std::vector<Instance> instances = collectInstances(path, ai, options, meshes);
  if (instances.empty()) {
    fail(ErrorCode::BadInput, path, "has no triangles (points and lines are not loaded)");
  }

  Scene scene;
  scene.name = std::filesystem::path(path).stem().string();
  buildGeometry(path, ai, instances, meshes, scene);
  computeBounds(scene);
  frameScene(path, scene);
  try {
    validateScene(scene);
  } catch (const Error& e) {
    fail(e.code(), path, e.what());
  }
  return scene;
}

}  // namespace logrid::samples::load
