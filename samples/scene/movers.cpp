#include "scene/movers.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include "logrid/error.hpp"
#include "scene/mesh_writer.hpp"

namespace logrid::samples {
namespace {

// Mesh shapes, each modelled facing +x with its feet or wheels on y = 0.
enum class Shape : std::uint8_t { Deer, Boar, Bear, Car, Van, Bus };

// Appends the mesh of a shape to the scene, scaled by `size`; returns its object (index
// range, colour, box).
class ShapeWriter {
 public:
  ShapeWriter(Scene& scene, double size, bool colors)
      : scene_(scene), w_(scene), size_(size), colors_(colors) {}

  SceneObject write(Shape shape) {
    SceneObject o;
    o.first_index = static_cast<std::uint32_t>(scene_.indices.size());
    const std::size_t first_vertex = scene_.positions.size() / 3;
    switch (shape) {
      case Shape::Deer: deer(); break;
      case Shape::Boar: boar(); break;
      case Shape::Bear: bear(); break;
      case Shape::Car: vehicle(4.2, 1.4, 1.8, 4, 2, 0.34, 4, rgba(170, 40, 36)); break;
      case Shape::Van: vehicle(5.2, 2.3, 2.0, 10, 4, 0.38, 4, rgba(220, 220, 214)); break;
      case Shape::Bus: vehicle(12.0, 3.1, 2.5, 36, 6, 0.5, 6, rgba(226, 170, 30)); break;
    }
    o.index_count = static_cast<std::uint32_t>(scene_.indices.size()) - o.first_index;
    o.color = color_;
    o.box = emptyBox();
    for (std::size_t v = first_vertex; v < scene_.positions.size() / 3; ++v) {
      growBox(o.box, &scene_.positions[v * 3]);
    }
    return o;
  }

 private:
  std::uint32_t vertex(double x, double y, double z, std::uint32_t c) {
    color_ = c;
    scene_.positions.insert(scene_.positions.end(),
                            {float(x * size_), float(y * size_), float(z * size_)});
    if (colors_) scene_.vertex_colors.push_back(c);  // only where the scene has them
    return static_cast<std::uint32_t>(scene_.positions.size() / 3 - 1);
  }

  // An ellipsoid: slices * 2 + slices * (stacks - 2) * 2 triangles.
  void ellipsoid(double cx, double cy, double cz, double rx, double ry, double rz, int slices,
                 int stacks, std::uint32_t c) {
    const std::uint32_t top = vertex(cx, cy + ry, cz, c);
    std::vector<std::uint32_t> rings;
    for (int k = 1; k < stacks; ++k) {
      const double phi = M_PI * k / stacks;
      const std::uint32_t first = std::uint32_t(scene_.positions.size() / 3);
      for (int s = 0; s < slices; ++s) {
        const double a = 2 * M_PI * s / slices;
        vertex(cx + rx * std::sin(phi) * std::cos(a), cy + ry * std::cos(phi),
               cz + rz * std::sin(phi) * std::sin(a), c);
      }
      rings.push_back(first);
    }
    const std::uint32_t bottom = vertex(cx, cy - ry, cz, c);
    for (int s = 0; s < slices; ++s) {
      const std::uint32_t i = std::uint32_t(s), n = std::uint32_t((s + 1) % slices);
      w_.triangle(top, rings[0] + n, rings[0] + i);
      for (std::size_t k = 0; k + 1 < rings.size(); ++k) {
        w_.quad(rings[k] + i, rings[k] + n, rings[k + 1] + n, rings[k + 1] + i);
      }
      w_.triangle(bottom, rings.back() + i, rings.back() + n);
    }
  }

  // A closed cylinder along `axis` (0 x, 1 y, 2 z) from `from` to from + length.
  void cylinder(double cx, double cy, double cz, int axis, double from, double length,
                double radius, int sides, std::uint32_t c) {
    auto at = [&](double along, double a) {
      double p[3] = {cx, cy, cz};
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      p[axis] = along;
      p[u] += radius * std::cos(a);
      p[v] += radius * std::sin(a);
      return vertex(p[0], p[1], p[2], c);
    };
    double centre[3] = {cx, cy, cz};
    centre[axis] = from;
    const std::uint32_t c0 = vertex(centre[0], centre[1], centre[2], c);
    centre[axis] = from + length;
    const std::uint32_t c1 = vertex(centre[0], centre[1], centre[2], c);
    const std::uint32_t first = std::uint32_t(scene_.positions.size() / 3);
    for (int s = 0; s < sides; ++s) {
      const double a = 2 * M_PI * s / sides;
      at(from, a);
      at(from + length, a);
    }
    for (int s = 0; s < sides; ++s) {
      const std::uint32_t a0 = first + 2 * std::uint32_t(s), a1 = a0 + 1;
      const std::uint32_t b0 = first + 2 * std::uint32_t((s + 1) % sides), b1 = b0 + 1;
      w_.quad(a0, b0, b1, a1);
      w_.triangle(c0, b0, a0);
      w_.triangle(c1, a1, b1);
    }
  }

  // A box [x0, x1] x [y0, y1] x [z0, z1] with each face divided into n x m quads.
  void box(double x0, double y0, double z0, double x1, double y1, double z1, int n, int m,
           std::uint32_t c) {
    const double lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
    for (int axis = 0; axis < 3; ++axis) {
      for (int side = 0; side < 2; ++side) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        const std::uint32_t first = std::uint32_t(scene_.positions.size() / 3);
        for (int j = 0; j <= m; ++j) {
          for (int i = 0; i <= n; ++i) {
            double p[3];
            p[axis] = side ? hi[axis] : lo[axis];
            p[u] = lo[u] + (hi[u] - lo[u]) * i / n;
            p[v] = lo[v] + (hi[v] - lo[v]) * j / m;
            vertex(p[0], p[1], p[2], c);
          }
        }
        for (int j = 0; j < m; ++j) {
          for (int i = 0; i < n; ++i) {
            const std::uint32_t a = first + std::uint32_t(j * (n + 1) + i);
            const std::uint32_t next_row = std::uint32_t(n + 1);
            if (side) {
              w_.quad(a, a + 1, a + 1 + next_row, a + next_row);
            } else {
              w_.quad(a, a + next_row, a + 1 + next_row, a + 1);
            }
          }
        }
      }
    }
  }

  void legs(double x_front, double x_back, double half_width, double height, double radius,
            int sides, std::uint32_t c) {
    for (double x : {x_front, x_back}) {
      for (double z : {-half_width, half_width}) cylinder(x, 0, z, 1, 0, height, radius, sides, c);
    }
  }

  void deer() {  // about 800 triangles
    const std::uint32_t fur = rgba(150, 104, 62);
    ellipsoid(0, 1.25, 0, 0.95, 0.38, 0.3, 20, 12, fur);
    ellipsoid(1.05, 1.75, 0, 0.3, 0.17, 0.14, 14, 8, fur);
    cylinder(0.8, 1.35, 0, 1, 1.35, 0.35, 0.1, 10, fur);
    legs(0.6, -0.6, 0.16, 1.05, 0.06, 8, rgba(110, 80, 50));
    color_ = fur;
  }
  void boar() {  // about 500 triangles
    const std::uint32_t hide = rgba(70, 58, 50);
    ellipsoid(0, 0.65, 0, 0.75, 0.38, 0.3, 16, 10, hide);
    ellipsoid(0.78, 0.62, 0, 0.28, 0.2, 0.18, 12, 8, hide);
    legs(0.45, -0.45, 0.16, 0.4, 0.07, 6, hide);
    color_ = hide;
  }
  void bear() {  // about 1,900 triangles
    const std::uint32_t fur = rgba(84, 60, 40);
    ellipsoid(0, 1.0, 0, 1.1, 0.62, 0.55, 32, 20, fur);
    ellipsoid(1.1, 1.25, 0, 0.36, 0.32, 0.3, 20, 12, fur);
    legs(0.65, -0.6, 0.3, 0.7, 0.16, 12, fur);
    color_ = fur;
  }
  // Body, cabin and wheels; `bays` divides the long faces (windows, panels).
  void vehicle(double length, double height, double width, int bays, int rows, double wheel,
               int wheels, std::uint32_t paint) {
    const double half_l = 0.5 * length, half_w = 0.5 * width, floor = wheel * 0.9;
    box(-half_l, floor, -half_w, half_l, height * 0.6, half_w, bays, rows, paint);
    box(-half_l * 0.6, height * 0.6, -half_w * 0.92, half_l * 0.5, height, half_w * 0.92,
        bays / 2 + 1, rows / 2 + 1, rgba(60, 80, 100));
    for (int k = 0; k < wheels / 2; ++k) {
      const double x =
          -half_l * 0.7 + (wheels > 4 ? 0.7 * length * k / (wheels / 2 - 1) : 1.4 * half_l * k);
      for (double side : {-1.0, 1.0}) {
        cylinder(x, wheel, side * half_w, 2, side > 0 ? half_w : -half_w - 0.25, 0.25, wheel, 16,
                 rgba(30, 30, 30));
      }
    }
    color_ = paint;
  }

  Scene& scene_;
  MeshWriter w_;
  double size_;
  bool colors_;
  std::uint32_t color_ = 0xFFFFFFFFu;
};

Shape pickShape(MoverKind kind, double r) {
  if (kind == MoverKind::Animals)
    return r < 0.5 ? Shape::Deer : r < 0.8 ? Shape::Boar : Shape::Bear;
  return r < 0.6 ? Shape::Car : r < 0.85 ? Shape::Van : Shape::Bus;
}

// Paths through the forest (or a file scene's floor): loops, and a tenth straight
// tracks reaching 25 % beyond the bounds on both sides.
MotionPath animalPath(std::size_t index, const Aabb& area, double size, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0, 1);
  const double cx = 0.5 * (double(area.min.x) + area.max.x),
               cz = 0.5 * (double(area.min.z) + area.max.z);
  const double ex = double(area.max.x) - area.min.x, ez = double(area.max.z) - area.min.z;
  const double floor = area.min.y;
  MotionPath path;
  path.follow_ground = true;
  if (index % 10 == 9) {
    const double angle = 2 * M_PI * unit(rng);
    const double dx = std::cos(angle), dz = std::sin(angle);
    const double ox = cx + (unit(rng) - 0.5) * 0.5 * ex, oz = cz + (unit(rng) - 0.5) * 0.5 * ez;
    // Far enough to leave the square area on both sides.
    const double reach = 0.75 * std::max(ex, ez);
    path.points = {{ox - dx * reach, floor, oz - dz * reach},
                   {ox + dx * reach, floor, oz + dz * reach}};
    return path;
  }
  const double x = area.min.x + (0.05 + 0.9 * unit(rng)) * ex;
  const double z = area.min.z + (0.05 + 0.9 * unit(rng)) * ez;
  const double radius = (8 + 42 * unit(rng)) * size, aspect = 0.5 + unit(rng);
  const double phase = 2 * M_PI * unit(rng);
  constexpr int kPoints = 8;
  for (int k = 0; k < kPoints; ++k) {
    const double a = phase + 2 * M_PI * k / kPoints;
    const double r = radius * (0.8 + 0.4 * unit(rng));
    path.points.push_back({x + r * std::cos(a), floor, z + r * aspect * std::sin(a)});
  }
  path.loop = true;
  return path;
}

// Routes along the city's streets: around one to three blocks, and every fifth along a
// whole street, reaching a quarter of the city beyond it on both sides. One lane per
// route, 3 m from the street's centre line.
MotionPath vehiclePath(std::size_t index, const MoverSite& site, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0, 1);
  const std::vector<double>& xs = site.streets_x;
  const std::vector<double>& zs = site.streets_z;
  auto pick = [&](std::size_t n) { return std::min(n - 1, std::size_t(unit(rng) * double(n))); };
  constexpr double kLane = 3.0;
  MotionPath path;
  if (index % 5 == 4) {
    const double span_x = xs.back() - xs.front(), span_z = zs.back() - zs.front();
    if (unit(rng) < 0.5) {
      const double z = zs[pick(zs.size())] + kLane;
      path.points = {{xs.front() - 0.25 * span_x, 0, z}, {xs.back() + 0.25 * span_x, 0, z}};
    } else {
      const double x = xs[pick(xs.size())] + kLane;
      path.points = {{x, 0, zs.front() - 0.25 * span_z}, {x, 0, zs.back() + 0.25 * span_z}};
    }
    return path;
  }
  const std::size_t i = pick(xs.size() - 1), j = pick(zs.size() - 1);
  const std::size_t a = std::min(xs.size() - 1, i + 1 + pick(3));
  const std::size_t b = std::min(zs.size() - 1, j + 1 + pick(3));
  const double x0 = xs[i] + kLane, x1 = xs[a] - kLane, z0 = zs[j] + kLane, z1 = zs[b] - kLane;
  path.points = {{x0, 0, z0}, {x1, 0, z0}, {x1, 0, z1}, {x0, 0, z1}};
  path.loop = true;
  return path;
}

}  // namespace

void addMovers(Scene& scene, std::uint32_t count, std::uint64_t seed) {
  if (count > kMaxMovers) {
    std::ostringstream out;
    out << "movers: " << count << " is too many; use at most " << kMaxMovers;
    throw Error(ErrorCode::InvalidArgument, out.str());
  }
  if (count == 0) return;
  MoverSite& site = scene.mover_site;
  const Aabb area = scene.bounds;
  const double extent =
      std::max({double(area.max.x) - area.min.x, double(area.max.z) - area.min.z, 1e-6});
  // Procedural scenes say their size (metres); a file's scene gets movers about 1 % of
  // its width long.
  const double size = site.size > 0 ? site.size : std::clamp(extent / 200.0, 1e-4, 1e4);
  const bool vehicles =
      site.kind == MoverKind::Vehicles && site.streets_x.size() >= 2 && site.streets_z.size() >= 2;
  std::mt19937_64 rng(seed ^ 0x6d6f76657273ull);  // "movers"
  std::uniform_real_distribution<double> unit(0, 1);

  Motion& motion = scene.motion;
  if (!motion.ground) {
    const double floor = area.min.y;
    motion.ground = site.ground ? site.ground : [floor](double, double) { return floor; };
  }
  const std::size_t paths = (count + 2) / 3;
  const std::size_t first_path = motion.paths.size();
  for (std::size_t p = 0; p < paths; ++p) {
    MotionPath path = vehicles ? vehiclePath(p, site, rng) : animalPath(p, area, size, rng);
    path.finish("movers: path " + std::to_string(p));
    motion.paths.push_back(std::move(path));
  }

  const bool colors = !scene.vertex_colors.empty() || scene.positions.empty();
  ShapeWriter writer(scene, size, colors);
  std::map<Shape, SceneObject> shapes;
  const MoverKind kind = vehicles ? MoverKind::Vehicles : MoverKind::Animals;
  for (std::uint32_t i = 0; i < count; ++i) {
    const Shape shape = pickShape(kind, unit(rng));
    auto it = shapes.find(shape);
    if (it == shapes.end()) it = shapes.emplace(shape, writer.write(shape)).first;
    const SceneObject& mesh = it->second;

    MoverSpec m;
    m.path = static_cast<std::uint32_t>(first_path + i % paths);
    const double speed = (vehicles ? 3 + 9 * unit(rng) : 0.5 + 2.5 * unit(rng)) * size;
    m.speed = unit(rng) < 0.5 ? speed : -speed;
    m.offset = unit(rng) * motion.paths[m.path].length();
    if (unit(rng) < 0.5) {
      m.move_seconds = 10 + 50 * unit(rng);
      m.stop_seconds = 5 + 35 * unit(rng);
      m.phase = unit(rng) * (m.move_seconds + m.stop_seconds);
    }
    m.turn = true;
    m.mesh_box = mesh.box;
    m.triangles = mesh.index_count / 3;
    motion.movers.push_back(m);
    scene.moving.push_back(mesh);
  }
}

void animateMeshes(Scene& scene, const std::string& motion_file) {
  if (scene.split_by_triangles) {
    throw Error(ErrorCode::InvalidArgument,
                "--animate moves the meshes of a scene from a file; the procedural scenes take "
                "--movers instead");
  }
  std::vector<MeshAnimation> animations = loadMeshAnimations(motion_file, scene.objects.size());
  if (animations.size() >= scene.objects.size()) {
    throw Error(ErrorCode::BadInput,
                "motion file '" + motion_file + "': animates every mesh; leave at least one still");
  }
  std::vector<std::uint8_t> moving(scene.objects.size(), 0);
  for (MeshAnimation& a : animations) {
    // World to the scene's local coordinates (the anchor follows).
    for (DVec3& p : a.path.points) {
      p = {p.x - scene.origin.x, p.y - scene.origin.y, p.z - scene.origin.z};
    }
    a.path.finish("motion file '" + motion_file + "'");
    a.spec.anchor = a.path.points.front();
    a.spec.path = static_cast<std::uint32_t>(scene.motion.paths.size());
    a.spec.mesh_box = scene.objects[a.mesh].box;
    a.spec.triangles = scene.objects[a.mesh].index_count / 3;
    scene.motion.paths.push_back(std::move(a.path));
    scene.motion.movers.push_back(a.spec);
    scene.moving.push_back(scene.objects[a.mesh]);
    moving[a.mesh] = 1;
  }
  std::vector<SceneObject> still;
  std::vector<OccluderModel> still_models;  // occluder models follow their objects
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    if (moving[o]) continue;
    still.push_back(scene.objects[o]);
    if (!scene.occluder_models.empty()) still_models.push_back(scene.occluder_models[o]);
  }
  scene.objects.swap(still);
  if (!scene.occluder_models.empty()) scene.occluder_models.swap(still_models);
}

}  // namespace logrid::samples
