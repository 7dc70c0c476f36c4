// The forest of LOG §5: hilly terrain in patches and a few thousand trees, each tree
// one object, seen from a trail at eye height. What matters for culling is the depth
// complexity along the trail (trunks and crowns hide most of the forest within a few
// tens of metres) and a comparable triangle count; trees are simple but readable.
#include <cmath>
#include <random>

#include "scene/generators.hpp"
#include "scene/mesh_writer.hpp"

namespace logrid::samples {
namespace {

constexpr double kBaseSide = 420.0;    // metres at scale 1
constexpr double kBaseTrees = 6000.0;  // trees at scale 1: ~1.7 M triangles in all
constexpr double kCell = 4.0;          // terrain cell size
constexpr int kPatchCells = 16;        // terrain cells per patch side (512 triangles)
constexpr double kEye = 1.7;           // eye height above the trail
constexpr int kConiferTiers = 5;       // cones per conifer

// Rolling hills: a few sine waves with seeded directions and phases.
class Terrain {
 public:
  explicit Terrain(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> angle(0, 2 * M_PI);
    for (int i = 0; i < 4; ++i) {
      const double a = angle(rng);
      waves_[i] = {std::cos(a), std::sin(a), angle(rng), 2 * M_PI / (90.0 + 60.0 * i),
                   3.2 / (1.0 + 0.7 * i)};
    }
  }
  double height(double x, double z) const {
    double h = 0;
    for (const Wave& w : waves_) h += w.amplitude * std::sin((w.dx * x + w.dz * z) * w.k + w.phase);
    return h;
  }

 private:
  struct Wave {
    double dx, dz, phase, k, amplitude;
  };
  Wave waves_[4];
};

// The trail: a wobbly loop around the centre, r(theta) in polar coordinates.
class Trail {
 public:
  Trail(double radius, std::mt19937_64& rng) : radius_(radius) {
    std::uniform_real_distribution<double> angle(0, 2 * M_PI);
    phase3_ = angle(rng);
    phase5_ = angle(rng);
  }
  double radiusAt(double theta) const {
    return radius_ *
           (1.0 + 0.15 * std::sin(3 * theta + phase3_) + 0.07 * std::sin(5 * theta + phase5_));
  }
  // Approximate distance of (x, z) from the trail: radial, good enough for clearance.
  double distance(double x, double z) const {
    return std::fabs(std::hypot(x, z) - radiusAt(std::atan2(z, x)));
  }

 private:
  double radius_;
  double phase3_ = 0, phase5_ = 0;
};

std::uint32_t jitter(std::mt19937_64& rng, int r, int g, int b, int spread) {
  std::uniform_int_distribution<int> d(-spread, spread);
  auto c = [](int v) { return std::max(0, std::min(255, v)); };
  return rgba(c(r + d(rng)), c(g + d(rng)), c(b + d(rng)));
}

// A ring of `segments` vertices at height y and radius r around (x, z).
std::uint32_t ring(MeshWriter& w, double x, double y, double z, double r, int segments,
                   double phase, std::uint32_t color) {
  std::uint32_t first = 0;
  for (int s = 0; s < segments; ++s) {
    const double a = phase + 2 * M_PI * s / segments;
    const std::uint32_t v =
        w.vertex(float(x + r * std::cos(a)), float(y), float(z + r * std::sin(a)), color);
    if (s == 0) first = v;
  }
  return first;
}

void trunk(MeshWriter& w, double x, double y0, double z, double height, double radius,
           std::uint32_t color) {
  constexpr int kSides = 8;
  const std::uint32_t bottom = ring(w, x, y0 - 0.5, z, radius, kSides, 0, color);
  const std::uint32_t top = ring(w, x, y0 + height, z, radius * 0.7, kSides, 0, color);
  for (int s = 0; s < kSides; ++s) {
    const std::uint32_t n = std::uint32_t((s + 1) % kSides);
    w.quad(bottom + std::uint32_t(s), bottom + n, top + n, top + std::uint32_t(s));
  }
}

// A cone with a closed base: 2 * segments triangles.
void cone(MeshWriter& w, double x, double y0, double z, double height, double radius,
          std::uint32_t color) {
  constexpr int kSegments = 24;
  const std::uint32_t base = ring(w, x, y0, z, radius, kSegments, 0.1, color);
  const std::uint32_t apex = w.vertex(float(x), float(y0 + height), float(z), color);
  const std::uint32_t centre = w.vertex(float(x), float(y0), float(z), color);
  for (int s = 0; s < kSegments; ++s) {
    const std::uint32_t a = base + std::uint32_t(s), b = base + std::uint32_t((s + 1) % kSegments);
    w.triangle(a, b, apex);
    w.triangle(b, a, centre);
  }
}

// An ellipsoid crown: slices * 2 + slices * (stacks - 2) * 2 triangles.
void ellipsoid(MeshWriter& w, double x, double y, double z, double rh, double rv,
               std::uint32_t color) {
  constexpr int kSlices = 16, kStacks = 10;
  const std::uint32_t top = w.vertex(float(x), float(y + rv), float(z), color);
  std::uint32_t rings[kStacks - 1];
  for (int k = 1; k < kStacks; ++k) {
    const double phi = M_PI * k / kStacks;
    rings[k - 1] = ring(w, x, y + rv * std::cos(phi), z, rh * std::sin(phi), kSlices, 0, color);
  }
  const std::uint32_t bottom = w.vertex(float(x), float(y - rv), float(z), color);
  for (int s = 0; s < kSlices; ++s) {
    const std::uint32_t n = std::uint32_t((s + 1) % kSlices), i = std::uint32_t(s);
    w.triangle(top, rings[0] + n, rings[0] + i);
    for (int k = 0; k + 1 < kStacks - 1; ++k) {
      w.quad(rings[k] + i, rings[k] + n, rings[k + 1] + n, rings[k + 1] + i);
    }
    w.triangle(bottom, rings[kStacks - 2] + i, rings[kStacks - 2] + n);
  }
}

// The occluder model of a tree (scene.hpp, OccluderModel): the trunk as it is (an open
// tube, 16 triangles) and each crown part, a closed convex cone or ellipsoid, replaced
// by the convex hull of some of its own vertices, which lies inside it: every third
// vertex of a cone's base ring with its apex and base centre (16 of 48 triangles), and
// every second vertex of three of an ellipsoid's nine rings with its poles (48 of 288).
// `first` is the tree's first vertex; the layout is the one trunk(), cone() and
// ellipsoid() write.
OccluderModel treeModel(const Scene& scene, std::uint32_t first, bool conifer, int tiers) {
  OccluderModel m;
  auto take = [&](std::uint32_t v) {
    const float* p = &scene.positions[std::size_t(v) * 3];
    m.positions.insert(m.positions.end(), p, p + 3);
    return std::uint32_t(m.positions.size() / 3 - 1);
  };
  auto quad = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
  };
  constexpr std::uint32_t kTrunkSides = 8;
  std::uint32_t trunk[2 * kTrunkSides];
  for (std::uint32_t i = 0; i < 2 * kTrunkSides; ++i) trunk[i] = take(first + i);
  for (std::uint32_t s = 0; s < kTrunkSides; ++s) {
    const std::uint32_t n = (s + 1) % kTrunkSides;
    quad(trunk[s], trunk[n], trunk[kTrunkSides + n], trunk[kTrunkSides + s]);
  }
  std::uint32_t v = first + 2 * kTrunkSides;
  if (conifer) {
    constexpr std::uint32_t kSegments = 24, kStep = 3, kKept = kSegments / kStep;
    for (int t = 0; t < tiers; ++t, v += kSegments + 2) {
      std::uint32_t ring[kKept];
      for (std::uint32_t i = 0; i < kKept; ++i) ring[i] = take(v + i * kStep);
      const std::uint32_t apex = take(v + kSegments), centre = take(v + kSegments + 1);
      for (std::uint32_t i = 0; i < kKept; ++i) {
        const std::uint32_t a = ring[i], b = ring[(i + 1) % kKept];
        m.indices.insert(m.indices.end(), {a, b, apex, b, a, centre});
      }
    }
  } else {
    constexpr std::uint32_t kSlices = 16, kStep = 2, kKept = kSlices / kStep;
    constexpr std::uint32_t kRings[3] = {1, 4, 7};  // of rings 0..8 (the poles excluded)
    const std::uint32_t top = take(v), bottom = take(v + 1 + 9 * kSlices);
    std::uint32_t ring[3][kKept];
    for (int r = 0; r < 3; ++r) {
      for (std::uint32_t i = 0; i < kKept; ++i) {
        ring[r][i] = take(v + 1 + kRings[r] * kSlices + i * kStep);
      }
    }
    for (std::uint32_t i = 0; i < kKept; ++i) {
      const std::uint32_t n = (i + 1) % kKept;
      m.indices.insert(m.indices.end(), {top, ring[0][n], ring[0][i]});
      for (int r = 0; r < 2; ++r) quad(ring[r][i], ring[r][n], ring[r + 1][n], ring[r + 1][i]);
      m.indices.insert(m.indices.end(), {bottom, ring[2][i], ring[2][n]});
    }
  }
  return m;
}

}  // namespace

const char* toString(TreeParts parts) {
  switch (parts) {
    case TreeParts::Whole: return "whole";
    case TreeParts::TrunkCrown: return "trunk-crown";
    case TreeParts::Tiers: return "tiers";
  }
  return "?";
}

namespace {

// Terrain patches, each one object (no occluder model: the mesh is simple enough).
void addTerrain(MeshWriter& w, Scene& scene, const Terrain& terrain, double side,
                std::mt19937_64& rng) {
  const int cells = std::max(2, int(std::ceil(side / kCell)));
  const double half = 0.5 * cells * kCell;
  for (int pz = 0; pz < cells; pz += kPatchCells) {
    for (int px = 0; px < cells; px += kPatchCells) {
      const int nx = std::min(kPatchCells, cells - px), nz = std::min(kPatchCells, cells - pz);
      w.beginObject();
      const std::uint32_t first = std::uint32_t(scene.vertex_colors.size());
      for (int j = 0; j <= nz; ++j) {
        for (int i = 0; i <= nx; ++i) {
          const double x = -half + (px + i) * kCell, z = -half + (pz + j) * kCell;
          const double h = terrain.height(x, z);
          const int shade = int(12 * h);
          w.vertex(float(x), float(h), float(z), jitter(rng, 78 + shade, 96 + shade, 48, 6));
        }
      }
      for (int j = 0; j < nz; ++j) {
        for (int i = 0; i < nx; ++i) {
          const std::uint32_t a = first + std::uint32_t(j * (nx + 1) + i);
          w.quad(a, a + std::uint32_t(nx + 1), a + std::uint32_t(nx + 2), a + 1);
        }
      }
      w.endObject();
      scene.occluder_models.emplace_back();
    }
  }
}

// Trees on a jittered grid, keeping the trail clear.
void addTrees(MeshWriter& w, Scene& scene, const Terrain& terrain, const Trail& trail, double side,
              const GeneratorOptions& options, std::mt19937_64& rng) {
  const double tree_count = std::max(1.0, std::round(kBaseTrees * options.scale));
  const double spacing = side / std::sqrt(tree_count);
  const int grid = std::max(1, int(std::round(side / spacing)));
  std::uniform_real_distribution<double> unit(0, 1);
  for (int gz = 0; gz < grid; ++gz) {
    for (int gx = 0; gx < grid; ++gx) {
      const double x = -0.5 * side + (gx + 0.1 + 0.8 * unit(rng)) * spacing;
      const double z = -0.5 * side + (gz + 0.1 + 0.8 * unit(rng)) * spacing;
      const double height = 8.0 + 14.0 * unit(rng);
      const bool conifer = unit(rng) < 0.6;
      const double crown = conifer ? 0.2 * height : 0.28 * height;
      if (trail.distance(x, z) < crown + 1.5) continue;
      const double y = terrain.height(x, z);
      const TreeParts parts = options.tree_parts;
      w.beginObject();
      const std::uint32_t first = std::uint32_t(scene.vertex_colors.size());
      trunk(w, x, y, z, conifer ? 0.3 * height : 0.55 * height, 0.15 + 0.02 * height,
            jitter(rng, 92, 64, 40, 12));
      if (parts != TreeParts::Whole) w.endObject(), w.beginObject();
      if (conifer) {
        const std::uint32_t green = jitter(rng, 34, 78, 44, 14);
        constexpr int kTiers = 5;
        static_assert(kTiers == kConiferTiers);
        // Branches down to the ground, as in a dense spruce stand.
        for (int t = 0; t < kTiers; ++t) {
          const double f = double(t) / kTiers;
          if (t > 0 && parts == TreeParts::Tiers) w.endObject(), w.beginObject();
          cone(w, x, y + height * (0.06 + 0.7 * f), z, height * 0.32, crown * (1.0 - 0.7 * f),
               green);
        }
      } else {
        ellipsoid(w, x, y + 0.62 * height, z, crown, 0.36 * height, jitter(rng, 70, 120, 46, 18));
      }
      w.endObject();
      // A tree split into parts keeps one model, with its last part (a model may hold
      // solids of several objects, scene.hpp); the other parts have none.
      scene.occluder_models.resize(scene.objects.size() - 1);
      scene.occluder_models.push_back(treeModel(scene, first, conifer, kConiferTiers));
    }
  }
}

// The walkthrough: the trail at eye height, looking a few metres ahead.
CameraPath trailPath(const Terrain& terrain, const Trail& trail) {
  std::vector<CameraKey> keys;
  constexpr int kKeys = 64;
  for (int k = 0; k <= kKeys; ++k) {
    const double t = 2 * M_PI * k / kKeys, ahead = t + 0.04;
    const double r = trail.radiusAt(t), ra = trail.radiusAt(ahead);
    const double x = r * std::cos(t), z = r * std::sin(t);
    const double xa = ra * std::cos(ahead), za = ra * std::sin(ahead);
    keys.push_back(
        {{x, terrain.height(x, z) + kEye, z}, {xa, terrain.height(xa, za) + kEye, za}, 0});
  }
  return CameraPath(std::move(keys));
}

}  // namespace

Scene makeForest(const GeneratorOptions& options) {
  checkScale("forest", options.scale, kMaxForestScale);
  std::mt19937_64 rng(options.seed);
  const Terrain terrain(rng);
  const double side = kBaseSide * std::sqrt(options.scale);
  const Trail trail(0.33 * side, rng);

  Scene scene;
  scene.name = "forest";
  MeshWriter w(scene);
  addTerrain(w, scene, terrain, side, rng);
  addTrees(w, scene, terrain, trail, side, options, rng);
  scene.path = trailPath(terrain, trail);
  scene.near_plane = 0.1;
  scene.far_plane = std::max(300.0, side);
  // Movers (--movers, movers.hpp): animals walking on the terrain.
  scene.mover_site.kind = MoverKind::Animals;
  scene.mover_site.ground = [terrain](double x, double z) { return terrain.height(x, z); };
  scene.mover_site.size = 1.0;
  computeBounds(scene);
  return scene;
}

}  // namespace logrid::samples
