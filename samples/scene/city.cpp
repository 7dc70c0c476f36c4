// The city of LOG §5: a street grid of blocks, each block divided into lots with a
// building of varied height, walls made of window bays (a frame around a window box
// that stands out of the wall). The triangle count comes from the facades, as in a detailed city
// model; the hierarchy is built over triangles. From the street, the nearest blocks hide almost
// everything else. Each building is a closed surface (walls, roof, floor), and carries
// an occluder solid, a box inside it, for the CPU occlusion buffer's models.
#include <array>
#include <cmath>
#include <random>

#include "logrid/error.hpp"
#include "scene/generators.hpp"
#include "scene/mesh_writer.hpp"

namespace logrid::samples {
namespace {

constexpr double kBlock = 76.0;   // block side, metres
constexpr double kStreet = 24.0;  // street width
constexpr double kPitch = kBlock + kStreet;
constexpr double kBaseBlocks = 1190;  // blocks at scale 1: ~34 M triangles
constexpr double kFloor = 3.5;        // storey height
constexpr double kBay = 4.0;          // window bay width
constexpr double kEye = 1.7;

struct Palette {
  std::uint32_t wall;
  std::uint32_t glass;
};

constexpr double kWindowDepth = 0.35;  // how far a window box stands out of its wall
constexpr double kWallInset = 0.5;     // the occluder box's distance behind each wall
constexpr double kFlatInset = 0.1;     // ... below the roof and above the floor
constexpr std::uint32_t kRoofColor = rgba(96, 92, 88);

int bayCount(double x0, double z0, double x1, double z1) {
  return std::max(1, int(std::hypot(x1 - x0, z1 - z0) / kBay));
}

// A point of the wall from (x0, z0) to (x1, z1): a fraction t along it, at height y,
// `out` in front of its face. t = 0 and t = 1 give (x0, z0) and (x1, z1) exactly and
// equal arguments give equal floats, so adjacent bays, storeys and walls, the roof and
// the floor meet vertex for vertex, bit for bit: no cracks, no T-junctions.
std::array<float, 3> wallPoint(double x0, double z0, double x1, double z1, double t, double y,
                               double out) {
  const double length = std::hypot(x1 - x0, z1 - z0);
  const double nx = -(z1 - z0) / length, nz = (x1 - x0) / length;  // outward normal
  return {float(x0 * (1 - t) + x1 * t + nx * out), float(y),
          float(z0 * (1 - t) + z1 * t + nz * out)};
}

// One wall from (x0, z0) to (x1, z1) (the outside to the left when seen from above,
// +y towards the eye, walking from 0 to 1), of `floors` storeys: a plain ground floor,
// then window bays of a frame (8 triangles) and a window box (10 triangles) standing
// kWindowDepth out of the wall.
void wall(MeshWriter& w, double x0, double z0, double x1, double z1, int floors, Palette p) {
  const int bays = bayCount(x0, z0, x1, z1);
  auto at = [&](double t, double y, double out) {
    return wallPoint(x0, z0, x1, z1, t / bays, y, out);
  };
  for (int f = 0; f < floors; ++f) {
    const double y0 = f * kFloor, y1 = (f + 1) * kFloor;
    for (int b = 0; b < bays; ++b) {
      const double s0 = b, s1 = b + 1;  // in bays
      const auto o00 = at(s0, y0, 0), o10 = at(s1, y0, 0), o11 = at(s1, y1, 0), o01 = at(s0, y1, 0);
      if (f == 0) {
        w.quad(o00.data(), o10.data(), o11.data(), o01.data(), p.wall);
        continue;
      }
      const double ws0 = s0 + 0.25, ws1 = s1 - 0.25;
      const double wy0 = y0 + 0.3 * kFloor, wy1 = y0 + 0.8 * kFloor;
      const std::uint32_t a = w.vertex(o00[0], o00[1], o00[2], p.wall);
      const std::uint32_t b_ = w.vertex(o10[0], o10[1], o10[2], p.wall);
      const std::uint32_t c = w.vertex(o11[0], o11[1], o11[2], p.wall);
      const std::uint32_t d = w.vertex(o01[0], o01[1], o01[2], p.wall);
      std::uint32_t in[4], back[4];
      const double corners[4][2] = {{ws0, wy0}, {ws1, wy0}, {ws1, wy1}, {ws0, wy1}};
      for (int k = 0; k < 4; ++k) {
        const auto fi = at(corners[k][0], corners[k][1], 0);
        const auto bi = at(corners[k][0], corners[k][1], kWindowDepth);
        in[k] = w.vertex(fi[0], fi[1], fi[2], p.wall);
        back[k] = w.vertex(bi[0], bi[1], bi[2], p.glass);
      }
      // Frame: below, right, above, left of the window.
      w.quad(a, b_, in[1], in[0]);
      w.quad(b_, c, in[2], in[1]);
      w.quad(c, d, in[3], in[2]);
      w.quad(d, a, in[0], in[3]);
      // Window box: four sides shading from wall to glass, and the glass.
      for (int k = 0; k < 4; ++k) {
        const int n = (k + 1) % 4;
        w.quad(in[k], in[n], back[n], back[k]);
      }
      w.quad(back[0], back[1], back[2], back[3]);
    }
  }
}

// A building on the lot [x0, x1] x [z0, z1]: four walls, and a flat roof and a floor,
// each a fan from its centre through every vertex of the walls' top or bottom edge. The
// triangles form one closed surface, consistently wound (every edge is shared
// by exactly two triangles, in opposite directions; scenes_test CityOccluders).
void building(MeshWriter& w, double x0, double z0, double x1, double z1, int floors, Palette p) {
  // Clockwise seen from above (+y towards the eye), so each wall has the outside on its left.
  const double corners[5][2] = {{x0, z1}, {x1, z1}, {x1, z0}, {x0, z0}, {x0, z1}};
  for (int k = 0; k < 4; ++k) {
    wall(w, corners[k][0], corners[k][1], corners[k + 1][0], corners[k + 1][1], floors, p);
  }
  const double h = floors * kFloor;
  const float cx = float(0.5 * (x0 + x1)), cz = float(0.5 * (z0 + z1));
  const std::uint32_t roof = w.vertex(cx, float(h), cz, kRoofColor);
  const std::uint32_t floor = w.vertex(cx, 0, cz, kRoofColor);
  for (int k = 0; k < 4; ++k) {
    const double* c0 = corners[k];
    const double* c1 = corners[k + 1];
    const int bays = bayCount(c0[0], c0[1], c1[0], c1[1]);
    for (int b = 0; b < bays; ++b) {
      auto vertex = [&](int i, double y) {
        const auto q = wallPoint(c0[0], c0[1], c1[0], c1[1], double(i) / bays, y, 0);
        return w.vertex(q[0], q[1], q[2], kRoofColor);
      };
      w.triangle(roof, vertex(b, h), vertex(b + 1, h));   // facing up
      w.triangle(floor, vertex(b + 1, 0), vertex(b, 0));  // facing down
    }
  }
}

// The occluder solid of a building (scene.hpp, OccluderSolid) whose vertices span
// `around`, and why its box lies inside the real geometry. The building's closed surface
// bounds the lot's prism P = [x0, x1] x [0, h] x [z0, z1] with the window boxes on it.
// Each of its triangles lies in a slab along one face F of P, from F's plane to
// kWindowDepth in front of it: the frames, the ground floor, the roof and the floor in
// F's plane, the window boxes' sides between it and kWindowDepth out, their glass
// kWindowDepth out. The box is P inset by kWallInset from the walls and kFlatInset from
// the roof and the floor, so no triangle meets it, and its centre is inside the surface:
// the box is inside the solid. The depth rule needs more, and has it. For a centre q the
// buffer claims for the box, q lies inside the box's projection, hence inside P's
// silhouette, by more than GL's snapping error s; the faces of P that the eye sees form
// a disk bounded by the silhouette, and their real triangles (sharing every edge vertex
// for vertex) a disk with the same boundary, so GL, after snapping, covers q with one of
// them, T, of a face F the eye sees. T lies on the eye's side of F's plane and the box
// behind it, so the point of T whose depth GL interpolates (within s of q, on a ray into
// the box) is nearer than the box; so is T's plane at q where T is parallel to F
// (llvmpipe evaluates the plane of the unsnapped triangle at q itself). Not covered:
// llvmpipe evaluating a window box's side, a plane across F, at a centre up to s past
// its edge on the wall, where the plane runs into the building; it reaches the box
// (kWallInset >= kWindowDepth behind the wall) only for a side whose projection is
// narrower than about s, seen almost edge-on. The insets are small because every metre
// of them is a gap in the buffer along each building's silhouette.
OccluderSolid buildingSolid(double x0, double z0, double x1, double z1, int floors,
                            const Aabb& around) {
  const double h = floors * kFloor;
  OccluderSolid s;
  s.around = around;
  s.inside = {{float(x0 + kWallInset), float(kFlatInset), float(z0 + kWallInset)},
              {float(x1 - kWallInset), float(h - kFlatInset), float(z1 - kWallInset)}};
  return s;
}

// Tags the triangles written since the last call with `solid` (kNoSolid: none).
void tagTriangles(Scene& scene, std::uint32_t solid) {
  scene.triangle_solids.resize(scene.triangleCount(), solid);
}

}  // namespace

Scene makeCity(const GeneratorOptions& options) {
  checkScale("city", options.scale, kMaxCityScale, " (scale 16 is about 540 million triangles)");
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0, 1);
  const int blocks = std::max(2, int(std::round(std::sqrt(kBaseBlocks * options.scale))));
  const double half = 0.5 * blocks * kPitch;

  Scene scene;
  scene.name = "city";
  scene.split_by_triangles = true;
  MeshWriter w(scene);
  const Palette palettes[] = {{rgba(196, 184, 160), rgba(40, 56, 80)},
                              {rgba(168, 92, 70), rgba(36, 48, 70)},
                              {rgba(150, 150, 156), rgba(56, 80, 100)},
                              {rgba(214, 206, 190), rgba(30, 44, 66)},
                              {rgba(120, 126, 136), rgba(70, 96, 120)}};
  for (int bz = 0; bz < blocks; ++bz) {
    for (int bx = 0; bx < blocks; ++bx) {
      const double x0 = -half + bx * kPitch + 0.5 * kStreet,
                   z0 = -half + bz * kPitch + 0.5 * kStreet;
      // Ground of the block and the streets around it.
      const float g[4][3] = {
          {float(x0 - 0.5 * kStreet), 0, float(z0 - 0.5 * kStreet)},
          {float(x0 + kBlock + 0.5 * kStreet), 0, float(z0 - 0.5 * kStreet)},
          {float(x0 + kBlock + 0.5 * kStreet), 0, float(z0 + kBlock + 0.5 * kStreet)},
          {float(x0 - 0.5 * kStreet), 0, float(z0 + kBlock + 0.5 * kStreet)}};
      w.quad(g[0], g[3], g[2], g[1], rgba(70, 70, 74));
      tagTriangles(scene, kNoSolid);  // a single quad: its own occluder
      // Taller towards the centre of the city.
      const double centre = 1.0 - std::hypot(x0 + 0.5 * kBlock, z0 + 0.5 * kBlock) / (1.42 * half);
      const int lots_x = 1 + int(unit(rng) * 3), lots_z = 1 + int(unit(rng) * 3);
      for (int lz = 0; lz < lots_z; ++lz) {
        for (int lx = 0; lx < lots_x; ++lx) {
          const double lw = kBlock / lots_x, ld = kBlock / lots_z;
          const double setback = 1.0 + 2.0 * unit(rng);
          const int floors = 3 + int((6 + 20 * centre) * unit(rng) + 8 * centre);
          const double bx0 = x0 + lx * lw + setback, bz0 = z0 + lz * ld + setback;
          const double bx1 = x0 + (lx + 1) * lw - setback, bz1 = z0 + (lz + 1) * ld - setback;
          const std::size_t first_vertex = scene.positions.size();
          building(w, bx0, bz0, bx1, bz1, floors,
                   palettes[std::size_t(unit(rng) * std::size(palettes)) % std::size(palettes)]);
          Aabb around = emptyBox();
          for (std::size_t v = first_vertex; v < scene.positions.size(); v += 3) {
            growBox(around, &scene.positions[v]);
          }
          tagTriangles(scene, std::uint32_t(scene.occluder_solids.size()));
          scene.occluder_solids.push_back(buildingSolid(bx0, bz0, bx1, bz1, floors, around));
        }
      }
      if (scene.indices.size() > (std::size_t(1) << 32) - 1) {
        throw Error(ErrorCode::InvalidArgument,
                    "city: too many triangles for 32-bit indices; use a smaller scale");
      }
    }
  }

  // The walkthrough: a random walk along the streets, never turning back, at street level.
  auto street = [&](int i) { return -half + i * kPitch; };  // street centre lines
  int ix = blocks / 2, iz = blocks / 2, dir = 0;
  const int dx[4] = {1, 0, -1, 0}, dz[4] = {0, 1, 0, -1};
  std::vector<CameraKey> keys;
  constexpr int kSegments = 24;
  for (int k = 0; k <= kSegments; ++k) {
    // Choose the next direction: straight on usually, a turn sometimes, never back.
    int next = dir;
    for (int attempt = 0; attempt < 8; ++attempt) {
      const double r = unit(rng);
      const int candidate = r < 0.5 ? dir : r < 0.75 ? (dir + 1) % 4 : (dir + 3) % 4;
      const int nx = ix + dx[candidate], nz = iz + dz[candidate];
      if (nx >= 0 && nx <= blocks && nz >= 0 && nz <= blocks) {
        next = candidate;
        break;
      }
      next = (dir + 2) % 4;  // a dead end at the city's edge: turn round
    }
    const glm::dvec3 p{street(ix), kEye, street(iz)};
    keys.push_back({p, p + glm::dvec3(10.0 * dx[next], 0, 10.0 * dz[next]), 0});
    dir = next;
    ix += dx[dir];
    iz += dz[dir];
  }
  scene.path = CameraPath(std::move(keys));
  scene.near_plane = 0.3;
  scene.far_plane = 1000.0;
  // Movers (--movers, movers.hpp): vehicles on the streets.
  scene.mover_site.kind = MoverKind::Vehicles;
  for (int i = 0; i <= blocks; ++i) scene.mover_site.streets_x.push_back(street(i));
  scene.mover_site.streets_z = scene.mover_site.streets_x;
  scene.mover_site.size = 1.0;
  computeBounds(scene);
  return scene;
}

}  // namespace logrid::samples
