// An indoor scene for the directional discretized occluders (DDO): an office building of
// three storeys, a corridor down the middle of each, rooms on both sides behind walls
// with a door each, furniture and shelves of books in the rooms, windows in the outer
// walls. Every wall, slab and piece of furniture is a closed box with shared corners, so
// the faces of octree nodes inside walls and slabs are valid occluders (DDO §3.2), which
// is what this scene is for; samples/cli/export.cpp writes it as a model file. The
// walkthrough follows the middle storey's corridor, glancing into the rooms.
#include <cmath>
#include <random>
#include <vector>

#include "scene/generators.hpp"
#include "scene/mesh_writer.hpp"

namespace logrid::samples {
namespace {

constexpr double kRoom = 5.0;      // room width along the corridor
constexpr double kDepth = 6.0;     // room depth
constexpr double kCorridor = 1.5;  // half width of the corridor
constexpr double kStorey = 3.2;    // floor to floor
constexpr double kSlab = 0.3;      // floor slab thickness
constexpr double kWall = 0.1;      // half thickness of a wall
constexpr int kStoreys = 3;
constexpr double kBaseRooms = 12;  // rooms on each side of a corridor at scale 1

constexpr double kTessellation = 0.5;  // largest quad side on walls, slabs and furniture

// A closed box (part of the current object), each face a grid of quads no larger than
// kTessellation, as a CAD model is finely tessellated. Grid points along each axis come
// from one expression, so the faces meeting at an edge share its vertices' positions
// exactly (the box is closed and watertight).
void box(MeshWriter& w, double x0, double y0, double z0, double x1, double y1, double z1,
         std::uint32_t color) {
  if (!(x1 > x0 && y1 > y0 && z1 > z0)) return;
  const double lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
  int n[3];
  for (int a = 0; a < 3; ++a) n[a] = std::max(1, int(std::ceil((hi[a] - lo[a]) / kTessellation)));
  auto coord = [&](int a, int i) { return i == n[a] ? hi[a] : lo[a] + (hi[a] - lo[a]) * i / n[a]; };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      std::vector<std::uint32_t> grid(std::size_t(n[u] + 1) * std::size_t(n[v] + 1));
      for (int i = 0; i <= n[u]; ++i) {
        for (int j = 0; j <= n[v]; ++j) {
          double p[3];
          p[axis] = side ? hi[axis] : lo[axis];
          p[u] = coord(u, i);
          p[v] = coord(v, j);
          grid[std::size_t(i) * std::size_t(n[v] + 1) + std::size_t(j)] =
              w.vertex(float(p[0]), float(p[1]), float(p[2]), color);
        }
      }
      for (int i = 0; i < n[u]; ++i) {
        for (int j = 0; j < n[v]; ++j) {
          auto at = [&](int a, int b) {
            return grid[std::size_t(a) * std::size_t(n[v] + 1) + std::size_t(b)];
          };
          // Outward facing: counter-clockwise seen from outside.
          if (side) {
            w.quad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
          } else {
            w.quad(at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
          }
        }
      }
    }
  }
}

// A box that is an object of its own.
void objectBox(MeshWriter& w, double x0, double y0, double z0, double x1, double y1, double z1,
               std::uint32_t color) {
  w.beginObject();
  box(w, x0, y0, z0, x1, y1, z1, color);
  w.endObject(color);
}

// A wall along x (at z, from x0 to x1) or along z, from y0 to y1, with openings given as
// [from, to, bottom, top] along its length: the wall is split into closed boxes around them.
struct Opening {
  double from, to, bottom, top;
};
void wall(MeshWriter& w, bool along_x, double at, double from, double to, double y0, double y1,
          const std::vector<Opening>& openings, std::uint32_t color) {
  auto piece = [&](double a, double b, double ya, double yb) {
    if (along_x) {
      objectBox(w, a, ya, at - kWall, b, yb, at + kWall, color);
    } else {
      objectBox(w, at - kWall, ya, a, at + kWall, yb, b, color);
    }
  };
  double cursor = from;
  for (const Opening& o : openings) {
    piece(cursor, o.from, y0, y1);
    piece(o.from, o.to, y0, o.bottom);  // below (a window's sill)
    piece(o.from, o.to, o.top, y1);     // above
    cursor = o.to;
  }
  piece(cursor, to, y0, y1);
}

void furnish(MeshWriter& w, std::mt19937_64& rng, double x0, double z0, double z1, double y) {
  std::uniform_real_distribution<double> unit(0, 1);
  const double zc = 0.5 * (z0 + z1), toward = z1 > z0 ? 1.0 : -1.0;
  const double far = z1 - toward * 0.4;
  // A desk and a chair in the middle, a cabinet by the side wall.
  const double dx = x0 + 1.5 + unit(rng);
  w.beginObject();
  box(w, dx, y + 0.72, zc - 0.4, dx + 1.6, y + 0.76, zc + 0.4, rgba(150, 110, 70));
  box(w, dx + 0.05, y, zc - 0.35, dx + 0.1, y + 0.72, zc + 0.35, rgba(120, 90, 60));
  box(w, dx + 1.5, y, zc - 0.35, dx + 1.55, y + 0.72, zc + 0.35, rgba(120, 90, 60));
  w.endObject(rgba(150, 110, 70));
  objectBox(w, dx + 0.5, y + 0.42, zc - toward * 0.9 - 0.25, dx + 1.0, y + 0.47,
            zc - toward * 0.9 + 0.25, rgba(60, 60, 70));
  objectBox(w, x0 + kRoom - 0.8, y, std::min(zc, far), x0 + kRoom - 0.3, y + 1.9, std::max(zc, far),
            rgba(180, 180, 170));
  // A shelf of books along the back wall: many small closed boxes, one object a level.
  const double shelf_z = far;
  for (int level = 0; level < 5; ++level) {
    w.beginObject();
    const double by = y + 0.1 + level * 0.38;
    box(w, x0 + 0.5, by - 0.02, std::min(shelf_z, shelf_z - toward * 0.3), x0 + 3.5, by,
        std::max(shelf_z, shelf_z - toward * 0.3), rgba(110, 80, 50));
    double bx = x0 + 0.55;
    while (bx < x0 + 3.4) {
      const double width = 0.03 + 0.05 * unit(rng), height = 0.2 + 0.12 * unit(rng);
      const std::uint32_t c =
          rgba(60 + int(150 * unit(rng)), 40 + int(120 * unit(rng)), 40 + int(120 * unit(rng)));
      box(w, bx, by, std::min(shelf_z, shelf_z - toward * 0.25), bx + width, by + height,
          std::max(shelf_z, shelf_z - toward * 0.25), c);
      bx += width + 0.005;
    }
    w.endObject(rgba(110, 80, 50));
  }
}

}  // namespace

Scene makeOffice(const GeneratorOptions& options) {
  checkScale("office", options.scale, kMaxOfficeScale);
  std::mt19937_64 rng(options.seed);
  const int rooms = std::max(2, int(std::round(kBaseRooms * options.scale)));
  const double length = rooms * kRoom, outer = kCorridor + kDepth;
  Scene scene;
  scene.name = "office";
  MeshWriter w(scene);
  const std::uint32_t concrete = rgba(170, 168, 160), plaster = rgba(225, 220, 205),
                      facade = rgba(140, 150, 165);
  for (int s = 0; s <= kStoreys; ++s) {
    // Floor slabs (the last one is the roof).
    const double y = s * kStorey;
    objectBox(w, -kWall, y - kSlab, -outer - kWall, length + kWall, y, outer + kWall, concrete);
    if (s == kStoreys) break;
    const double y1 = y + kStorey - kSlab;
    // Outer walls with a window per room.
    std::vector<Opening> windows;
    for (int r = 0; r < rooms; ++r)
      windows.push_back({r * kRoom + 1.2, r * kRoom + 3.8, y + 0.9, y + 2.3});
    wall(w, true, outer, 0, length, y, y1, windows, facade);
    wall(w, true, -outer, 0, length, y, y1, windows, facade);
    wall(w, false, -kWall, -outer, outer, y, y1, {}, facade);
    wall(w, false, length + kWall, -outer, outer, y, y1, {}, facade);
    // Corridor walls with a door per room; walls between rooms.
    std::vector<Opening> doors;
    for (int r = 0; r < rooms; ++r) doors.push_back({r * kRoom + 2.0, r * kRoom + 3.0, y, y + 2.1});
    wall(w, true, kCorridor, 0, length, y, y1, doors, plaster);
    wall(w, true, -kCorridor, 0, length, y, y1, doors, plaster);
    for (int r = 1; r < rooms; ++r) {
      wall(w, false, r * kRoom, kCorridor + kWall, outer - kWall, y, y1, {}, plaster);
      wall(w, false, r * kRoom, -outer + kWall, -kCorridor - kWall, y, y1, {}, plaster);
    }
    for (int r = 0; r < rooms; ++r) {
      furnish(w, rng, r * kRoom, kCorridor + kWall, outer - kWall, y);
      furnish(w, rng, r * kRoom, -kCorridor - kWall, -outer + kWall, y);
    }
  }

  // Down the middle storey's corridor, looking ahead and into the rooms now and then.
  const double eye = kStorey + 1.6;
  std::vector<CameraKey> keys;
  for (int r = 0; r <= rooms; ++r) {
    const double x = std::min(length - 0.5, std::max(0.5, r * kRoom + 0.5));
    const double side = r % 3 == 1 ? 1.0 : r % 3 == 2 ? -1.0 : 0.0;
    const glm::dvec3 at{x, eye, 0.6 * side};
    const glm::dvec3 look = side == 0 ? glm::dvec3{x + 10, eye - 0.3, 0}
                                      : glm::dvec3{x + 1.5, eye - 0.2, side * (kCorridor + 3)};
    keys.push_back({at, look, 0});
  }
  scene.path = CameraPath(std::move(keys));
  scene.near_plane = 0.1;
  scene.far_plane = 200.0;
  computeBounds(scene);
  return scene;
}

}  // namespace logrid::samples
