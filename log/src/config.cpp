// The configuration file (config.hpp): reader and writer.
#include "logrid/config.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <locale>
#include <sstream>

#include "json_reader.hpp"
#include "logrid/error.hpp"

namespace logrid {
namespace {

using detail::Json;

constexpr detail::JsonFileKind kConfigFile{
    "configuration file", "write one with `logrid tune --auto --write-config FILE`"};

// Reads the values of a configuration; the first value it cannot read is its error
// (those after it are left as they were).
class ConfigReader {
 public:
  explicit ConfigReader(const std::string& origin) : origin_(origin) {}

  void bad(const std::string& what) {
    error_.note(Status(ErrorCode::BadInput, origin_ + ": " + what));
  }
  bool failed() const { return error_.failed(); }
  Status takeError() { return error_.take(); }

  // The object `key` of `parent`; an empty one if it is missing or not an object.
  const Json& object(const Json& parent, const char* key, const char* where) {
    static const Json kEmpty{Json::Kind::Object, false, 0, {}, {}};
    const Json* v = parent.find(key);
    if (!v || v->kind != Json::Kind::Object) {
      bad(std::string(where) + "\"" + key + "\" is missing or not an object");
      return kEmpty;
    }
    return *v;
  }

  void flag(const Json& parent, const char* key, bool& out) {
    const Json* v = parent.find(key);
    if (!v) return;
    if (v->kind != Json::Kind::Bool)
      return bad(std::string("\"") + key + "\" is not true or false");
    out = v->boolean;
  }

  void count(const Json& parent, const char* key, std::uint32_t& out) {
    const Json* v = parent.find(key);
    if (!v) return;
    constexpr double kMax = std::numeric_limits<std::uint32_t>::max();
    if (v->kind != Json::Kind::Number || !(v->number >= 0 && v->number <= kMax) ||
        std::floor(v->number) != v->number) {
      return bad(std::string("\"") + key + "\" is not a whole number in [0, 4294967295]");
    }
    out = std::uint32_t(v->number);
  }

  // Parsed as a float from the number's text (one rounding: formatCullerConfig's shortest
  // text of a float reads back as that float); below a float's range it is that double
  // rounded (0 or a denormal).
  void fraction(const Json& parent, const char* key, float& out) {
    const Json* v = parent.find(key);
    if (!v) return;
    float f = std::numeric_limits<float>::quiet_NaN();
    if (v->kind == Json::Kind::Number) {
      const std::from_chars_result r =
          std::from_chars(v->text.data(), v->text.data() + v->text.size(), f);
      if (r.ec == std::errc::result_out_of_range) f = float(v->number);
    }
    if (!(f >= 0 && f <= 1)) return bad(std::string("\"") + key + "\" is not a number in [0, 1]");
    out = f;
  }

  void lookahead(const Json& parent, std::uint32_t& out) {
    const Json* v = parent.find("lookahead");
    if (v && v->kind == Json::Kind::String) {
      if (v->text != "all")
        return bad("\"lookahead\" is \"" + v->text + "\"; use a count or \"all\"");
      out = kUnlimitedLookahead;
      return;
    }
    count(parent, "lookahead", out);
  }

  void method(const Json& parent, Method& out) {
    const Json* v = parent.find("method");
    if (!v) return;
    if (v->kind != Json::Kind::String) return bad("\"method\" is not a method's name");
    const std::optional<Method> m = parseMethod(v->text);
    if (!m) return bad("method \"" + v->text + "\" is unknown; use " + methodNames());
    out = *m;
  }

 private:
  const std::string& origin_;
  FirstError error_;
};

}  // namespace

Result<CullerConfig> tryParseCullerConfig(const std::string& text, const std::string& origin) {
  Result<std::unique_ptr<Json>> parsed = detail::parseJson(text, origin, kConfigFile);
  if (!parsed) return parsed.status();
  const Json* doc = parsed->get();
  ConfigReader r(origin);
  if (doc->kind != Json::Kind::Object) r.bad("a configuration file is one JSON object");
  const Json* format = doc->find("format");
  if (!format || format->kind != Json::Kind::String || format->text != "logrid-config") {
    r.bad("\"format\" is not \"logrid-config\"; " + std::string(kConfigFile.remedy));
  }
  const Json* version = doc->find("version");
  if (!version || version->kind != Json::Kind::Number || version->number != 1) {
    r.bad("\"version\" is not 1, the only version this logrid reads");
  }
  if (r.failed()) return r.takeError();
  CullerConfig config;
  if (const Json* source = doc->find("source")) {
    if (source->kind != Json::Kind::String) r.bad("\"source\" is not a depth source's name");
    config.source = source->text;
  }
  const Json& c = r.object(*doc, "culler", "");
  CullerDesc& d = config.culler;
  r.method(c, d.method);
  r.count(c, "tile_size", d.tile_size);
  r.lookahead(c, d.lookahead);
  r.flag(c, "temporal_coherence", d.temporal_coherence);
  r.flag(c, "detect_colliding", d.detect_colliding);
  if (c.find("approximation")) {
    const Json& a = r.object(c, "approximation", "culler: ");
    r.count(a, "visible_pixels", d.approximation.visible_pixels);
    r.fraction(a, "full_free_fraction", d.approximation.full_free_fraction);
    r.count(a, "row_stride", d.approximation.row_stride);
  }
  if (r.failed()) return r.takeError();
  const std::string problem = validateCullerDesc(d);
  if (!problem.empty()) r.bad(problem);
  if (r.failed()) return r.takeError();
  return config;
}

Result<CullerConfig> tryLoadCullerConfig(const std::string& path) {
  Result<std::string> text = detail::readTextFile(path, kConfigFile);
  if (!text) return text.status();
  return tryParseCullerConfig(*text, path);
}

std::string formatCullerConfig(const CullerConfig& config) {
  const CullerDesc& d = config.culler;
  std::ostringstream out;
  out.imbue(std::locale::classic());  // no digit grouping whatever the global locale
  out << "{\n  \"format\": \"logrid-config\",\n  \"version\": 1,\n  \"source\": \""
      << detail::jsonEscape(config.source) << "\",\n  \"culler\": {\n    \"method\": \""
      << toString(d.method) << "\",\n    \"tile_size\": " << d.tile_size
      << ",\n    \"lookahead\": ";
  if (d.lookahead == kUnlimitedLookahead) {
    out << "\"all\"";
  } else {
    out << d.lookahead;
  }
  out << ",\n    \"temporal_coherence\": " << (d.temporal_coherence ? "true" : "false")
      << ",\n    \"detect_colliding\": " << (d.detect_colliding ? "true" : "false")
      << ",\n    \"approximation\": {\"visible_pixels\": " << d.approximation.visible_pixels
      << ", \"full_free_fraction\": " << detail::jsonNumber(d.approximation.full_free_fraction)
      << ", \"row_stride\": " << d.approximation.row_stride << "}\n  }\n}\n";
  return out.str();
}

}  // namespace logrid
