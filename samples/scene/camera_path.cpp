#include "scene/camera_path.hpp"

#include <algorithm>
#include <cassert>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string_view>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "logrid/error.hpp"
#include "scene/json_file.hpp"

namespace logrid::samples {
namespace {

// Limits that keep every later computation finite. No real scene comes near them, but
// a hostile file can: with coordinates within 1e100, differences, squared lengths and
// the sum of a million segment lengths all stay far below DBL_MAX, and times within
// 1e200 can be subtracted and scaled without overflow.
constexpr double kMaxCoordinate = 1e100;
constexpr double kMaxTime = 1e200;
// Hostile-input guards for JSON: a real path is a few hundred keys and kilobytes.
constexpr std::size_t kMaxJsonBytes = std::size_t{64} << 20;
constexpr std::size_t kMaxKeys = 1000000;

using glm::dvec3;

// Vector arithmetic is GLM's; these are the few checks it has no single call for.
bool isFinite(const dvec3& a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
double maxAbs(const dvec3& a) { return std::max({std::abs(a.x), std::abs(a.y), std::abs(a.z)}); }
// hypot instead of glm::length (sqrt of the dot product) so that tiny separations do not
// underflow to zero.
double length(const dvec3& a) { return std::hypot(a.x, a.y, a.z); }
// glm::mix computes a (1 - u) + b u, which returns a and b exactly at u = 0 and u = 1
// (a + (b - a) u would not).
double lerp(double a, double b, double u) { return glm::mix(a, b, u); }

// Shortest text that reads back as the same double, so that messages show the values
// the user wrote (0.1, not 0.100000000000000006).
std::string str(double v) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, result.ptr);
}
std::string str(const dvec3& v) { return "(" + str(v.x) + ", " + str(v.y) + ", " + str(v.z) + ")"; }

// The first problem with the key values and up vector, or "" (times are checked
// separately because JSON paths without times get theirs only after this check).
std::string checkValues(const std::vector<CameraKey>& keys, const dvec3& up) {
  const std::string range = str(kMaxCoordinate);
  if (!isFinite(up) || maxAbs(up) > kMaxCoordinate) {
    return "up " + str(up) + " must be finite and within +-" + range + "; use e.g. (0, 1, 0)";
  }
  if (!(glm::dot(up, up) >= DBL_MIN)) {
    return "up " + str(up) + " has (almost) zero length; use a direction such as (0, 1, 0)";
  }
  if (keys.empty()) return "no keys; a camera path needs at least one key";
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const CameraKey& k = keys[i];
    const std::string label = "key " + std::to_string(i);
    const std::pair<const char*, dvec3> points[] = {{"position", k.position},
                                                    {"look_at", k.look_at}};
    for (const auto& [name, v] : points) {
      if (!isFinite(v)) {
        return label + " has a non-finite " + name + " " + str(v) +
               "; every coordinate must be a finite number";
      }
      if (maxAbs(v) > kMaxCoordinate) {
        return label + " has " + name + " " + str(v) + " out of range; keep coordinates within +-" +
               range;
      }
    }
    if (k.position == k.look_at) {
      return label + " has position == look_at " + str(k.position) +
             "; the camera needs a direction, so move look_at away from the position";
    }
    // lookAt normalises look_at - position; its squared length must not underflow.
    const dvec3 view = k.look_at - k.position;
    if (!(glm::dot(view, view) >= DBL_MIN)) {
      return label + " has look_at " + str(k.look_at) + " only " + str(length(view)) +
             " away from position " + str(k.position) +
             "; the camera needs a direction, so move look_at further away";
    }
  }
  return {};
}

std::string checkTimes(const std::vector<CameraKey>& keys) {
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const double t = keys[i].time;
    const std::string label = "key " + std::to_string(i);
    if (!std::isfinite(t) || std::abs(t) > kMaxTime) {
      return label + " has time " + str(t) + "; times must be finite and within +-" + str(kMaxTime);
    }
    if (i > 0 && !(t > keys[i - 1].time)) {
      return label + " has time " + str(t) + ", not after key " + std::to_string(i - 1) +
             "'s time " + str(keys[i - 1].time) + "; times must increase strictly from key to key";
    }
  }
  return {};
}

// Constant speed: each key's time is the distance the position has travelled. Segments
// in which the position does not move (the camera only turns) would get no time at all,
// so they get the mean length of the moving segments instead, and when nothing moves
// every segment lasts 1 (keys spaced evenly by index). A segment counts as moving only
// if it is not negligible next to the whole path, which also guarantees that adding it
// to the running time changes the time (times must increase strictly).
void assignConstantSpeedTimes(std::vector<CameraKey>& keys) {
  std::vector<double> lengths(keys.size() > 0 ? keys.size() - 1 : 0);
  double total = 0;
  for (std::size_t i = 0; i < lengths.size(); ++i) {
    lengths[i] = length(keys[i + 1].position - keys[i].position);
    total += lengths[i];
  }
  const double negligible = total * 1e-12;
  double moving_total = 0;
  std::size_t moving = 0;
  for (double l : lengths) {
    if (l > negligible) moving_total += l, ++moving;
  }
  const double still_length = moving > 0 ? moving_total / static_cast<double>(moving) : 1.0;
  double time = 0;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    keys[i].time = time;
    if (i < lengths.size()) time += lengths[i] > negligible ? lengths[i] : still_length;
  }
}

// Centripetal knot spacing between two points: |b - a|^0.5, i.e. the fourth root of the
// squared distance.
double knotGap(const dvec3& a, const dvec3& b) {
  const dvec3 d = b - a;
  return std::sqrt(std::sqrt(glm::dot(d, d)));
}

// (b - a) / gap, and zero when the gap is zero: that is the limit as the points merge,
// because |b - a| / |b - a|^0.5 -> 0. This is what makes coincident neighbours (and the
// duplicated end points) harmless instead of a division by zero.
dvec3 chordOver(const dvec3& a, const dvec3& b, double gap) {
  return gap > 0 ? (b - a) / gap : dvec3(0.0);
}

// The centripetal Catmull-Rom segment from p1 (u = 0) to p2 (u = 1), with p0 and p3 as
// neighbours. Written in Hermite form with the tangents of the Barry-Goldman pyramid
// (Yuksel et al., "Parameterization and applications of Catmull-Rom curves") because the
// pyramid's weights, such as (t1 - t) / (t1 - t0), blow up when a neighbour is close;
// here every term is a chord over its own knot gap, bounded by |d|^0.5, so close or
// coincident neighbours cause neither overflow nor amplified rounding.
dvec3 catmullRom(const dvec3& p0, const dvec3& p1, const dvec3& p2, const dvec3& p3, double u) {
  const double g0 = knotGap(p0, p1);
  const double g1 = knotGap(p1, p2);
  const double g2 = knotGap(p2, p3);
  // Coincident segment ends: there is no curve to speak of, and the tangents below would
  // divide by zero.
  if (!(g1 > 0)) return glm::mix(p1, p2, u);
  const dvec3 m1 =
      (chordOver(p0, p1, g0) - chordOver(p0, p2, g0 + g1) + chordOver(p1, p2, g1)) * g1;
  const dvec3 m2 =
      (chordOver(p1, p2, g1) - chordOver(p1, p3, g1 + g2) + chordOver(p2, p3, g2)) * g1;
  const double v = 1 - u;
  const double h00 = (1 + 2 * u) * v * v;
  const double h10 = u * v * v;
  const double h01 = u * u * (3 - 2 * u);
  const double h11 = -u * u * v;
  const dvec3 p = (p1 * h00 + m1 * h10) + (p2 * h01 + m2 * h11);
  // The input limits (kMaxCoordinate) keep every term above finite.
  assert(isFinite(p));
  return p;
}

// An interpolated camera can end up (almost) on its look-at point, e.g. when it flies
// through the point it looks at. A lookAt cannot build a view from that, so then the
// look-at point is moved off the position along the blend of the segment's two key view
// directions (which are valid by construction) -- not along the direction of travel,
// which is zero when the camera only turns and backwards when it retreats. When the two
// key directions nearly cancel, the nearer key's direction is used. The distance is the
// blend of the keys' eye-to-target distances, at least enough to survive rounding at the
// position's magnitude.
dvec3 usableLookAt(const dvec3& position, const dvec3& look_at, const CameraKey& a,
                   const CameraKey& b, double u) {
  const dvec3 view_a = a.look_at - a.position;
  const dvec3 view_b = b.look_at - b.position;
  const double gap_a = length(view_a);
  const double gap_b = length(view_b);
  const dvec3 view = look_at - position;
  // 1e-6 of the keys' own separation: below that the direction is mostly rounding noise.
  if (glm::dot(view, view) >= DBL_MIN && length(view) >= 1e-6 * std::min(gap_a, gap_b)) {
    return look_at;
  }
  const dvec3 dir_a = view_a / gap_a;
  const dvec3 dir_b = view_b / gap_b;
  dvec3 dir = glm::mix(dir_a, dir_b, u);
  const double dir_length = length(dir);
  dir = dir_length > 0.1 ? dir / dir_length : (u < 0.5 ? dir_a : dir_b);
  const double distance = std::max(lerp(gap_a, gap_b, u), 1e-9 * maxAbs(position));
  return position + dir * distance;
}

CameraPose poseOf(const CameraKey& key, const dvec3& up) { return {key.position, key.look_at, up}; }

// ---------------------------------------------------------------------------------------
// JSON reading. A SAX handler rather than a parsed document: memory stays proportional
// to the keys (a DOM of a 64 MiB hostile file can take gigabytes), the key limit is
// enforced while reading, and every message can name the key and field it is about.
// ---------------------------------------------------------------------------------------

struct ReadKey {
  CameraKey key;
  bool has_position = false;
  bool has_look_at = false;
  bool has_time = false;
};

class PathReader {
 public:
  using Json = nlohmann::json;

  // The SAX interface of nlohmann::json. Returning false stops the parser; error()
  // then says why.
  bool null() { return value(Kind::Null, 0); }
  bool boolean(bool) { return value(Kind::Boolean, 0); }
  bool number_integer(Json::number_integer_t v) {
    return value(Kind::Number, static_cast<double>(v));
  }
  bool number_unsigned(Json::number_unsigned_t v) {
    return value(Kind::Number, static_cast<double>(v));
  }
  bool number_float(Json::number_float_t v, const std::string&) { return value(Kind::Number, v); }
  bool string(std::string&) { return value(Kind::String, 0); }
  bool binary(Json::binary_t&) { return value(Kind::Binary, 0); }
  bool start_object(std::size_t) { return value(Kind::Object, 0); }
  bool start_array(std::size_t) { return value(Kind::Array, 0); }
  bool key(std::string& name);
  bool end_object() { return end(); }
  bool end_array() { return end(); }
  bool parse_error(std::size_t position, const std::string&, const Json::exception& ex);

  const std::string& error() const { return error_; }
  std::vector<ReadKey>& keys() { return keys_; }
  bool hasUp() const { return has_up_; }
  dvec3 up() const { return up_; }

 private:
  enum class Kind { Null, Boolean, Number, String, Binary, Object, Array };
  enum class State {
    Document,  // before the root value
    Root,      // in the root object, between fields
    Keys,      // in the "keys" array, between keys
    Key,       // in a key object, between fields
    Vector,    // in a [x, y, z] array
    Skip,      // inside a value of a field this format does not use
    Done,
  };
  enum class Field { None, Keys, Up, Position, LookAt, Time, Other };

  static const char* describe(Kind kind);
  bool value(Kind kind, double number);
  bool fieldValue(Kind kind, double number);
  bool vectorElement(Kind kind, double number);
  bool end();
  bool fail(std::string message) {
    error_ = std::move(message);
    return false;
  }
  // "key 3 \"position\"" or "\"up\"": the field being read, for messages.
  std::string where() const;
  bool* seenFlag(Field field);

  State state_ = State::Document;
  Field field_ = Field::None;  // the field whose value comes next (Root and Key states)
  State skip_return_ = State::Root;
  std::size_t skip_depth_ = 0;
  dvec3* vector_ = nullptr;  // the [x, y, z] being filled
  std::size_t vector_count_ = 0;
  bool has_keys_ = false;
  bool has_up_ = false;
  dvec3 up_{0, 1, 0};
  std::vector<ReadKey> keys_;
  std::string error_;
};

const char* PathReader::describe(Kind kind) {
  switch (kind) {
    case Kind::Null: return "null";
    case Kind::Boolean: return "a boolean";
    case Kind::Number: return "a number";
    case Kind::String: return "a string";
    case Kind::Binary: return "binary data";
    case Kind::Object: return "an object";
    case Kind::Array: return "an array";
  }
  return "?";
}

std::string PathReader::where() const {
  const char* name = field_ == Field::Position ? "\"position\""
                     : field_ == Field::LookAt ? "\"look_at\""
                     : field_ == Field::Time   ? "\"time\""
                     : field_ == Field::Up     ? "\"up\""
                                               : "\"keys\"";
  if (field_ == Field::Position || field_ == Field::LookAt || field_ == Field::Time) {
    return "key " + std::to_string(keys_.size() - 1) + " " + name;
  }
  return name;
}

bool* PathReader::seenFlag(Field field) {
  switch (field) {
    case Field::Keys: return &has_keys_;
    case Field::Up: return &has_up_;
    case Field::Position: return &keys_.back().has_position;
    case Field::LookAt: return &keys_.back().has_look_at;
    case Field::Time: return &keys_.back().has_time;
    case Field::None:
    case Field::Other: break;
  }
  return nullptr;
}

bool PathReader::key(std::string& name) {
  if (state_ == State::Root) {
    field_ = name == "keys" ? Field::Keys : name == "up" ? Field::Up : Field::Other;
  } else if (state_ == State::Key) {
    field_ = name == "position"  ? Field::Position
             : name == "look_at" ? Field::LookAt
             : name == "time"    ? Field::Time
                                 : Field::Other;
  } else {
    return true;  // inside a skipped object
  }
  if (bool* seen = seenFlag(field_); seen != nullptr && *seen) {
    return fail(where() + " appears twice; give each field once");
  }
  return true;
}

bool PathReader::value(Kind kind, double number) {
  const bool opens = kind == Kind::Object || kind == Kind::Array;
  switch (state_) {
    case State::Document:
      if (kind != Kind::Object) {
        return fail(std::string("the document is ") + describe(kind) +
                    "; it must be a JSON object like {\"keys\": [{\"position\": [x, y, z], "
                    "\"look_at\": [x, y, z]}]}");
      }
      state_ = State::Root;
      return true;
    case State::Root:
    case State::Key: return fieldValue(kind, number);
    case State::Keys:
      if (kind != Kind::Object) {
        return fail("key " + std::to_string(keys_.size()) + " is " + describe(kind) +
                    "; each key must be an object with \"position\" and \"look_at\"");
      }
      if (keys_.size() >= kMaxKeys) {
        return fail("has more than " + std::to_string(kMaxKeys) +
                    " keys; that is no hand-made camera path, so thin it out or split it");
      }
      keys_.emplace_back();
      state_ = State::Key;
      return true;
    case State::Vector: return vectorElement(kind, number);
    case State::Skip:
      if (opens) ++skip_depth_;
      return true;
    case State::Done: break;
  }
  return fail("unexpected JSON value after the document");
}

bool PathReader::fieldValue(Kind kind, double number) {
  const bool opens = kind == Kind::Object || kind == Kind::Array;
  if (field_ == Field::Other || field_ == Field::None) {
    // Unknown fields are ignored (room for comments and extensions), skipping nested values.
    if (opens) skip_return_ = state_, skip_depth_ = 1, state_ = State::Skip;
    return true;
  }
  *seenFlag(field_) = true;
  switch (field_) {
    case Field::Keys:
      if (kind != Kind::Array) {
        return fail(std::string("\"keys\" is ") + describe(kind) +
                    "; it must be an array of key objects");
      }
      state_ = State::Keys;
      return true;
    case Field::Time:
      if (kind != Kind::Number) {
        return fail(where() + " is " + describe(kind) + "; it must be a number (seconds)");
      }
      keys_.back().key.time = number;
      return true;
    case Field::Up:
    case Field::Position:
    case Field::LookAt:
      if (kind != Kind::Array) {
        return fail(where() + " is " + describe(kind) + "; it must be an array [x, y, z]");
      }
      vector_ = field_ == Field::Up         ? &up_
                : field_ == Field::Position ? &keys_.back().key.position
                                            : &keys_.back().key.look_at;
      vector_count_ = 0;
      state_ = State::Vector;
      return true;
    case Field::None:
    case Field::Other: break;
  }
  return true;
}

bool PathReader::vectorElement(Kind kind, double number) {
  if (kind != Kind::Number) {
    return fail(where() + " element " + std::to_string(vector_count_) + " is " + describe(kind) +
                "; it must be an array of 3 numbers [x, y, z]");
  }
  if (vector_count_ == 3) {
    return fail(where() + " has more than 3 numbers; it must be an array [x, y, z]");
  }
  dvec3& v = *vector_;
  (vector_count_ == 0 ? v.x : vector_count_ == 1 ? v.y : v.z) = number;
  ++vector_count_;
  return true;
}

bool PathReader::end() {
  switch (state_) {
    case State::Skip:
      if (--skip_depth_ == 0) state_ = skip_return_;
      return true;
    case State::Vector:
      if (vector_count_ != 3) {
        return fail(where() + " has " + std::to_string(vector_count_) +
                    " numbers; it must be an array of 3 numbers [x, y, z]");
      }
      state_ = field_ == Field::Up ? State::Root : State::Key;
      return true;
    case State::Key: {
      const ReadKey& k = keys_.back();
      const std::string label = "key " + std::to_string(keys_.size() - 1);
      if (!k.has_position) return fail(label + " has no \"position\"; every key needs [x, y, z]");
      if (!k.has_look_at) return fail(label + " has no \"look_at\"; every key needs [x, y, z]");
      state_ = State::Keys;
      return true;
    }
    case State::Keys: state_ = State::Root; return true;
    case State::Root:
      if (!has_keys_) {
        return fail(
            "has no \"keys\"; give {\"keys\": [{\"position\": [x, y, z], \"look_at\": "
            "[x, y, z]}, ...]}");
      }
      state_ = State::Done;
      return true;
    case State::Document:
    case State::Done: break;
  }
  return fail("unbalanced JSON");
}

bool PathReader::parse_error(std::size_t position, const std::string&, const Json::exception& ex) {
  // Prefer the exception's byte index, as nlohmann documents it (1-based).
  const auto* syntax = dynamic_cast<const Json::parse_error*>(&ex);
  const std::size_t byte = syntax != nullptr ? syntax->byte : position;
  // Drop nlohmann's "[json.exception.parse_error.101] " tag; the rest says what it saw.
  std::string_view detail = ex.what();
  if (const std::size_t tag_end = detail.find("] ");
      !detail.empty() && detail.front() == '[' && tag_end != std::string_view::npos) {
    detail.remove_prefix(tag_end + 2);
  }
  // The detail quotes the last token, which in a hostile file can be megabytes long.
  constexpr std::size_t kMaxDetail = 240;
  const std::string shown = detail.size() > kMaxDetail
                                ? std::string(detail.substr(0, kMaxDetail)) + "..."
                                : std::string(detail);
  return fail("invalid JSON at byte " + std::to_string(byte) + " (" + shown +
              "); fix the JSON text there");
}

}  // namespace

CameraPath::CameraPath(std::vector<CameraKey> keys, glm::dvec3 up)
    : keys_(std::move(keys)), up_(up) {
  // Keys that all leave `time` at its default are untimed, as in JSON without times.
  const bool untimed =
      keys_.size() > 1 &&
      std::all_of(keys_.begin(), keys_.end(), [](const CameraKey& k) { return k.time == 0; });
  if (untimed) assignConstantSpeedTimes(keys_);
  std::string problem = checkValues(keys_, up_);
  if (problem.empty()) problem = checkTimes(keys_);
  if (!problem.empty()) throw Error(ErrorCode::InvalidArgument, "camera path: " + problem);
}

CameraPath CameraPath::fromJsonFile(const std::string& path) {
  const std::string text =
      readBoundedFile(path, "camera path '" + path + "': ", kMaxJsonBytes,
                      "camera path files are limited to 64 MiB, so thin out the keys");
  return fromJsonText(text, path);
}

CameraPath CameraPath::fromJsonText(const std::string& text, const std::string& name) {
  const std::string prefix = "camera path '" + name + "': ";
  const auto fail = [&](const std::string& what) {
    throw Error(ErrorCode::BadInput, prefix + what);
  };
  if (text.size() > kMaxJsonBytes) {
    fail("the JSON text is " + std::to_string(text.size()) +
         " bytes; camera paths are limited to 64 MiB, so thin out the keys");
  }
  PathReader reader;
  bool ok = false;
  try {
    ok = nlohmann::json::sax_parse(text, &reader);
  } catch (const nlohmann::json::exception& e) {
    // The SAX parser reports errors through parse_error(); this is only a safety net.
    fail(std::string("invalid JSON: ") + e.what());
  }
  if (!ok) fail(reader.error().empty() ? "invalid JSON" : reader.error());

  std::vector<ReadKey>& read = reader.keys();
  const dvec3 up = reader.hasUp() ? reader.up() : dvec3(0, 1, 0);
  for (std::size_t i = 1; i < read.size(); ++i) {
    if (read[i].has_time != read[0].has_time) {
      fail("key " + std::to_string(i) + (read[i].has_time ? " has a" : " has no") +
           " \"time\" but key 0 " + (read[0].has_time ? "has one" : "has none") +
           "; give every key a time, or none for constant speed");
    }
  }
  std::vector<CameraKey> keys;
  keys.reserve(read.size());
  for (const ReadKey& k : read) keys.push_back(k.key);
  if (std::string problem = checkValues(keys, up); !problem.empty()) fail(problem);
  if (!read.empty() && !read[0].has_time) assignConstantSpeedTimes(keys);
  if (std::string problem = checkTimes(keys); !problem.empty()) fail(problem);
  return CameraPath(std::move(keys), up);
}

double CameraPath::duration() const {
  return keys_.empty() ? 0.0 : keys_.back().time - keys_.front().time;
}

std::string CameraPath::toJsonText() const {
  auto vec = [](const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
  nlohmann::json keys = nlohmann::json::array();
  for (const CameraKey& k : keys_) {
    keys.push_back({{"position", vec(k.position)}, {"look_at", vec(k.look_at)}, {"time", k.time}});
  }
  // nlohmann writes doubles with the shortest text that reads back to the same value.
  return nlohmann::json{{"keys", keys}, {"up", vec(up_)}}.dump(1) + "\n";
}

CameraPose CameraPath::at(double time) const {
  if (keys_.empty()) {
    throw Error(ErrorCode::InvalidArgument,
                "camera path: at() on an empty path; construct the path from at least one key");
  }
  if (std::isnan(time)) {
    throw Error(ErrorCode::InvalidArgument,
                "camera path: at() got time nan; pass a number (it is clamped to the path)");
  }
  // The first key strictly after `time`; the segment starts at the key before it.
  const auto after = std::upper_bound(keys_.begin(), keys_.end(), time,
                                      [](double t, const CameraKey& k) { return t < k.time; });
  if (after == keys_.begin()) return poseOf(keys_.front(), up_);
  const std::size_t i = static_cast<std::size_t>(after - keys_.begin()) - 1;
  // Key times (and everything past the end) return the key itself, bit for bit.
  if (after == keys_.end() || keys_[i].time == time) return poseOf(keys_[i], up_);

  const CameraKey& a = keys_[i];
  const CameraKey& b = keys_[i + 1];
  const double u = std::clamp((time - a.time) / (b.time - a.time), 0.0, 1.0);
  // Phantom neighbours at the ends duplicate the end keys (chordOver makes them benign).
  // With centripetal knots that gives the path zero speed at its first and last key: the
  // camera eases in and out, which suits a walkthrough that starts and ends at rest.
  const CameraKey& before = i > 0 ? keys_[i - 1] : a;
  const CameraKey& beyond = i + 2 < keys_.size() ? keys_[i + 2] : b;
  CameraPose pose;
  pose.position = catmullRom(before.position, a.position, b.position, beyond.position, u);
  pose.look_at = catmullRom(before.look_at, a.look_at, b.look_at, beyond.look_at, u);
  pose.look_at = usableLookAt(pose.position, pose.look_at, a, b, u);
  pose.up = up_;
  return pose;
}

CameraPose CameraPath::frame(std::size_t frame, std::size_t frames) const {
  return at(frameTime(frame, frames));
}

double CameraPath::frameTime(std::size_t frame, std::size_t frames) const {
  if (frames == 0) {
    throw Error(ErrorCode::InvalidArgument,
                "camera path: frame() with frames == 0; ask for at least one frame");
  }
  if (frame >= frames) {
    throw Error(ErrorCode::InvalidArgument, "camera path: frame " + std::to_string(frame) +
                                                " is out of range for " + std::to_string(frames) +
                                                " frames; use 0 to " + std::to_string(frames - 1));
  }
  if (keys_.empty()) {
    at(0);  // throws the empty-path error
    return 0.0;
  }
  // The last frame takes the last key's time exactly rather than first + duration.
  if (frame + 1 == frames && frames > 1) return keys_.back().time;
  const double fraction =
      frames == 1 ? 0.0 : static_cast<double>(frame) / static_cast<double>(frames - 1);
  return keys_.front().time + duration() * fraction;
}

}  // namespace logrid::samples
