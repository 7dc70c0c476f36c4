#include "scene/motion.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include "logrid/error.hpp"
#include "scene/json_file.hpp"

namespace logrid::samples {
namespace {

constexpr double kUlp = 1.0 / 16777216.0;  // 2^-24
constexpr std::size_t kMaxJsonBytes = std::size_t(64) << 20;

bool finite(const DVec3& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

double distance(const DVec3& a, const DVec3& b) {
  return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) +
                   (a.z - b.z) * (a.z - b.z));
}

// The float nearest below / above a double (outward rounding of box bounds).
float down(double v) {
  float f = static_cast<float>(v);
  if (double(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float up(double v) {
  float f = static_cast<float>(v);
  if (double(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

bool sameBox(const Aabb& a, const Aabb& b) {
  return a.min.x == b.min.x && a.min.y == b.min.y && a.min.z == b.min.z && a.max.x == b.max.x &&
         a.max.y == b.max.y && a.max.z == b.max.z;
}

// The box of `b` (mesh coordinates) moved by `t`: see motion.hpp.
Aabb movedBox(const RigidTransform& t, const Aabb& b) {
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-lo[0], -lo[1], -lo[2]};
  double size = 0;
  for (int c = 0; c < 8; ++c) {
    const double q[3] = {(c & 1) ? b.max.x : b.min.x, (c & 2) ? b.max.y : b.min.y,
                         (c & 4) ? b.max.z : b.min.z};
    size = std::max(size, std::fabs(q[0]) + std::fabs(q[1]) + std::fabs(q[2]));
    for (int r = 0; r < 3; ++r) {
      const double v = t.rotation[r] * q[0] + t.rotation[3 + r] * q[1] + t.rotation[6 + r] * q[2];
      lo[r] = std::min(lo[r], v);
      hi[r] = std::max(hi[r], v);
    }
  }
  // The renderer's float rotation: its rounded elements and three products and sums are
  // off by a few ulps of the local coordinates' size; 16 ulps cover them.
  const double pad = 16 * kUlp * size;
  const double tr[3] = {t.translation.x, t.translation.y, t.translation.z};
  Aabb out;
  out.min = {down(lo[0] - pad + tr[0]), down(lo[1] - pad + tr[1]), down(lo[2] - pad + tr[2])};
  out.max = {up(hi[0] + pad + tr[0]), up(hi[1] + pad + tr[1]), up(hi[2] + pad + tr[2])};
  return out;
}

}  // namespace

void MotionPath::finish(const std::string& what) {
  auto fail = [&](const std::string& problem) {
    throw Error(ErrorCode::BadInput, what + ": " + problem);
  };
  if (points.size() < 2) fail("a path needs at least two points");
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!finite(points[i])) fail("path point " + std::to_string(i) + " is not finite");
  }
  cumulative.assign(1, 0.0);
  for (std::size_t i = 1; i < points.size(); ++i) {
    cumulative.push_back(cumulative.back() + distance(points[i - 1], points[i]));
  }
  if (loop) cumulative.push_back(cumulative.back() + distance(points.back(), points.front()));
  if (!(cumulative.back() > 0)) fail("the path has zero length (all points equal)");
}

double Motion::travelled(std::size_t i, double time) const {
  const MoverSpec& m = movers[i];
  double moving = time;
  if (m.stop_seconds > 0 && m.move_seconds > 0) {
    // Stop and go: move_seconds moving, then stop_seconds standing; at time 0 the mover
    // is `phase` seconds into that cycle. Moving time since time 0:
    const double cycle = m.move_seconds + m.stop_seconds;
    auto movingUntil = [&](double t) {
      const double cycles = std::floor(t / cycle);
      return cycles * m.move_seconds + std::min(t - cycles * cycle, m.move_seconds);
    };
    moving = movingUntil(time + m.phase) - movingUntil(m.phase);
  }
  return m.offset + m.speed * moving;
}

RigidTransform Motion::transformAt(std::size_t i, double time) const {
  const MoverSpec& m = movers[i];
  const MotionPath& path = paths[m.path];
  const double length = path.length();
  double s = travelled(i, time);
  // Around a loop; back and forth along an open path.
  double direction = m.speed >= 0 ? 1.0 : -1.0;
  if (path.loop) {
    s = std::fmod(s, length);
    if (s < 0) s += length;
  } else {
    double t = std::fmod(s, 2 * length);
    if (t < 0) t += 2 * length;
    if (t > length) {
      t = 2 * length - t;
      direction = -direction;
    }
    s = t;
  }
  const std::size_t segments = path.cumulative.size() - 1;
  std::size_t k = std::size_t(std::upper_bound(path.cumulative.begin(), path.cumulative.end(), s) -
                              path.cumulative.begin());
  k = std::min(std::max<std::size_t>(k, 1), segments) - 1;
  const DVec3& a = path.points[k];
  const DVec3& b = path.points[(k + 1) % path.points.size()];
  const double span = path.cumulative[k + 1] - path.cumulative[k];
  const double u = span > 0 ? std::clamp((s - path.cumulative[k]) / span, 0.0, 1.0) : 0.0;
  DVec3 p{a.x + u * (b.x - a.x), a.y + u * (b.y - a.y), a.z + u * (b.z - a.z)};
  if (path.follow_ground && ground) p.y = ground(p.x, p.z);

  RigidTransform t;
  if (m.turn) {
    double dx = (b.x - a.x) * direction, dz = (b.z - a.z) * direction;
    const double h = std::hypot(dx, dz);
    if (h > 0) {
      dx /= h, dz /= h;
    } else {
      dx = 1, dz = 0;
    }
    // Columns: local +x to (dx, 0, dz), +y stays, +z to (-dz, 0, dx) (a turn about +y).
    const double r[9] = {dx, 0, dz, 0, 1, 0, -dz, 0, dx};
    std::copy(r, r + 9, t.rotation);
  }
  t.translation = {p.x - m.anchor.x, p.y - m.anchor.y, p.z - m.anchor.z};
  return t;
}

std::uint32_t Motion::moverOf(std::size_t k) const {
  return parts.empty() ? static_cast<std::uint32_t>(k) : parts[k].mover;
}

const Aabb& Motion::meshBoxOf(std::size_t k) const {
  return parts.empty() ? movers[k].mesh_box : parts[k].mesh_box;
}

Aabb Motion::boxAt(std::size_t i, double time) const {
  return movedBox(transformAt(i, time), movers[i].mesh_box);
}

Aabb Motion::movingBoxAt(std::size_t k, double time) const {
  return movedBox(transformAt(moverOf(k), time), meshBoxOf(k));
}

void evaluateMotion(const Motion& motion, ObjectId first_mover, double time, MotionFrame& frame) {
  frame.time = time;
  frame.moved.clear();
  frame.transforms.resize(motion.movingObjects());
  std::size_t mover = motion.movers.size();  // whose transform `t` is
  RigidTransform t;
  for (std::size_t k = 0; k < motion.movingObjects(); ++k) {
    const ObjectId id = first_mover + static_cast<ObjectId>(k);
    if (motion.moverOf(k) != mover) {  // a mover's parts follow each other: one transform
      mover = motion.moverOf(k);
      t = motion.transformAt(mover, time);
    }
    frame.transforms[k] = t;
    const Aabb box = movedBox(t, motion.meshBoxOf(k));
    if (!sameBox(box, frame.boxes[id])) {
      frame.boxes[id] = box;
      frame.moved.push_back(id);
    }
  }
}

std::vector<MeshAnimation> loadMeshAnimations(const std::string& file, std::size_t object_count) {
  const std::string prefix = "motion file '" + file + "': ";
  auto fail = [&](const std::string& what) { throw Error(ErrorCode::BadInput, prefix + what); };
  const std::string text = readBoundedFile(file, prefix, kMaxJsonBytes, "");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    // parse_error, and out_of_range for a number beyond double (1e1111...).
    fail(std::string("is not valid JSON (") + e.what() + ")");
  }
  if (!j.is_object() || !j.contains("objects") || !j["objects"].is_array()) {
    fail("needs an object with an \"objects\" array");
  }
  auto number = [&](const nlohmann::json& o, const char* key, double fallback,
                    const std::string& where) {
    if (!o.contains(key)) return fallback;
    if (!o[key].is_number()) fail(where + ": \"" + key + "\" must be a number");
    const double v = o[key].get<double>();
    if (!std::isfinite(v)) fail(where + ": \"" + key + "\" must be finite");
    return v;
  };
  std::vector<MeshAnimation> out;
  std::set<std::uint32_t> seen;
  for (std::size_t k = 0; k < j["objects"].size(); ++k) {
    const nlohmann::json& o = j["objects"][k];
    const std::string where = "objects[" + std::to_string(k) + "]";
    if (!o.is_object()) fail(where + " must be an object");
    if (!o.contains("mesh") || !o["mesh"].is_number_unsigned()) {
      fail(where + ": \"mesh\" must be a mesh index (0 or more)");
    }
    const std::uint64_t mesh = o["mesh"].get<std::uint64_t>();
    if (mesh >= object_count) {
      fail(where + ": mesh " + std::to_string(mesh) + " does not exist (the scene has " +
           std::to_string(object_count) + " meshes)");
    }
    if (!seen.insert(std::uint32_t(mesh)).second) {
      fail(where + ": mesh " + std::to_string(mesh) + " is animated twice");
    }
    MeshAnimation a;
    a.mesh = std::uint32_t(mesh);
    if (!o.contains("path") || !o["path"].is_array()) fail(where + ": \"path\" must be an array");
    for (const nlohmann::json& p : o["path"]) {
      if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() ||
          !p[2].is_number()) {
        fail(where + ": path points must be [x, y, z] numbers");
      }
      a.path.points.push_back({p[0].get<double>(), p[1].get<double>(), p[2].get<double>()});
    }
    if (o.contains("loop")) {
      if (!o["loop"].is_boolean()) fail(where + ": \"loop\" must be true or false");
      a.path.loop = o["loop"].get<bool>();
    }
    a.path.finish(prefix + where);
    a.spec.speed = number(o, "speed", 1.0, where);
    a.spec.move_seconds = number(o, "move_seconds", 0.0, where);
    a.spec.stop_seconds = number(o, "stop_seconds", 0.0, where);
    a.spec.offset = number(o, "offset", 0.0, where);
    if (a.spec.move_seconds < 0 || a.spec.stop_seconds < 0) {
      fail(where + ": move_seconds and stop_seconds must be 0 or more");
    }
    if (a.spec.stop_seconds > 0 && a.spec.move_seconds == 0) {
      fail(where + ": stop_seconds needs move_seconds > 0 (a mover that never moves)");
    }
    a.spec.turn = false;
    a.spec.anchor = a.path.points.front();
    out.push_back(std::move(a));
  }
  return out;
}

}  // namespace logrid::samples
