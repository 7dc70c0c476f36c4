// The city of LOG §5: a street grid of blocks, each block divided into lots with a
// building of varied height, walls made of window bays (a frame around a recessed
// window). The triangle count comes from the facades, as in a detailed city model; the
// hierarchy is built over triangles. From the street, the nearest blocks hide almost
// everything else.
#include <array>
#include <cmath>
#include <random>
#include <sstream>

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

// One wall from (x0, z0) to (x1, z1) (outward normal to the right when seen from
// above, walking from 0 to 1), of `floors` storeys: a plain ground floor, then window
// bays of a frame (8 triangles) and a recess (10 triangles).
void wall(MeshWriter& w, double x0, double z0, double x1, double z1, int floors, Palette p) {
  const double length = std::hypot(x1 - x0, z1 - z0);
  const int bays = std::max(1, int(length / kBay));
  const double ux = (x1 - x0) / length, uz = (z1 - z0) / length;
  const double nx = uz, nz = -ux;  // outward normal
  constexpr double kInset = 0.35;
  auto at = [&](double s, double y, double depth) {
    return std::array<float, 3>{float(x0 + ux * s - nx * depth), float(y),
                                float(z0 + uz * s - nz * depth)};
  };
  const double bay = length / bays;
  for (int f = 0; f < floors; ++f) {
    const double y0 = f * kFloor, y1 = y0 + kFloor;
    for (int b = 0; b < bays; ++b) {
      const double s0 = b * bay, s1 = s0 + bay;
      const auto o00 = at(s0, y0, 0), o10 = at(s1, y0, 0), o11 = at(s1, y1, 0), o01 = at(s0, y1, 0);
      if (f == 0) {
        w.quad(o00.data(), o10.data(), o11.data(), o01.data(), p.wall);
        continue;
      }
      const double ws0 = s0 + 0.25 * bay, ws1 = s1 - 0.25 * bay;
      const double wy0 = y0 + 0.3 * kFloor, wy1 = y0 + 0.8 * kFloor;
      const std::uint32_t a = w.vertex(o00[0], o00[1], o00[2], p.wall);
      const std::uint32_t b_ = w.vertex(o10[0], o10[1], o10[2], p.wall);
      const std::uint32_t c = w.vertex(o11[0], o11[1], o11[2], p.wall);
      const std::uint32_t d = w.vertex(o01[0], o01[1], o01[2], p.wall);
      std::uint32_t in[4], back[4];
      const double corners[4][2] = {{ws0, wy0}, {ws1, wy0}, {ws1, wy1}, {ws0, wy1}};
      for (int k = 0; k < 4; ++k) {
        const auto fi = at(corners[k][0], corners[k][1], 0);
        const auto bi = at(corners[k][0], corners[k][1], kInset);
        in[k] = w.vertex(fi[0], fi[1], fi[2], p.wall);
        back[k] = w.vertex(bi[0], bi[1], bi[2], p.glass);
      }
      // Frame: below, right, above, left of the window.
      w.quad(a, b_, in[1], in[0]);
      w.quad(b_, c, in[2], in[1]);
      w.quad(c, d, in[3], in[2]);
      w.quad(d, a, in[0], in[3]);
      // Recess: four sides shading from wall to glass, and the glass.
      for (int k = 0; k < 4; ++k) {
        const int n = (k + 1) % 4;
        w.quad(in[k], in[n], back[n], back[k]);
      }
      w.quad(back[0], back[1], back[2], back[3]);
    }
  }
}

void building(MeshWriter& w, double x0, double z0, double x1, double z1, int floors, Palette p) {
  // Counter-clockwise seen from above (+y), so each wall's outward normal is on its right.
  wall(w, x0, z1, x1, z1, floors, p);
  wall(w, x1, z1, x1, z0, floors, p);
  wall(w, x1, z0, x0, z0, floors, p);
  wall(w, x0, z0, x0, z1, floors, p);
  const float h = float(floors * kFloor);
  const float r0[3] = {float(x0), h, float(z0)}, r1[3] = {float(x1), h, float(z0)};
  const float r2[3] = {float(x1), h, float(z1)}, r3[3] = {float(x0), h, float(z1)};
  w.quad(r0, r3, r2, r1, rgba(96, 92, 88));
}

}  // namespace

Scene makeCity(const GeneratorOptions& options) {
  if (!(options.scale > 0) || !std::isfinite(options.scale) || options.scale > 16) {
    std::ostringstream out;
    out << "city: scale " << options.scale
        << " is out of range; use a value in (0, 16] (scale 16 is about 540 million triangles)";
    throw Error(ErrorCode::InvalidArgument, out.str());
  }
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
      // Taller towards the centre of the city.
      const double centre = 1.0 - std::hypot(x0 + 0.5 * kBlock, z0 + 0.5 * kBlock) / (1.42 * half);
      const int lots_x = 1 + int(unit(rng) * 3), lots_z = 1 + int(unit(rng) * 3);
      for (int lz = 0; lz < lots_z; ++lz) {
        for (int lx = 0; lx < lots_x; ++lx) {
          const double lw = kBlock / lots_x, ld = kBlock / lots_z;
          const double setback = 1.0 + 2.0 * unit(rng);
          const int floors = 3 + int((6 + 20 * centre) * unit(rng) + 8 * centre);
          building(w, x0 + lx * lw + setback, z0 + lz * ld + setback, x0 + (lx + 1) * lw - setback,
                   z0 + (lz + 1) * ld - setback, floors,
                   palettes[std::size_t(unit(rng) * std::size(palettes)) % std::size(palettes)]);
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
