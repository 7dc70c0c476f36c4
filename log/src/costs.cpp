// The costs file (costs.hpp), its reader and writer, and the online estimate.
#include "logrid/costs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <vector>

#include "json_reader.hpp"
#include "logrid/error.hpp"

namespace logrid {
namespace {

using detail::Json;

constexpr detail::JsonFileKind kCostsFile{"costs file",
                                          "write one with `logrid calibrate --costs FILE`"};

struct CostField {
  const char* name;
  double CullerCosts::*member;
};

constexpr CostField kFields[] = {
    {"flush_s", &CullerCosts::flush_s},       {"pixel_s", &CullerCosts::pixel_s},
    {"box_test_s", &CullerCosts::box_test_s}, {"triangle_s", &CullerCosts::triangle_s},
    {"draw_s", &CullerCosts::draw_s},         {"query_s", &CullerCosts::query_s},
};

Status bad(const std::string& origin, const std::string& what) {
  return Status(ErrorCode::BadInput, origin + ": " + what);
}

}  // namespace

std::string validateCullerCosts(const CullerCosts& costs) {
  for (const CostField& f : kFields) {
    const double v = costs.*f.member;
    if (!(std::isfinite(v) && v > 0 && v <= 1)) {
      std::ostringstream out;
      out << "costs: " << f.name << " = " << v
          << " is not a time in (0, 1] seconds; measure it with `logrid calibrate`";
      return out.str();
    }
  }
  return {};
}

Result<CullerCostsFile> tryParseCullerCosts(const std::string& text, const std::string& origin) {
  Result<std::unique_ptr<Json>> parsed = detail::parseJson(text, origin, kCostsFile);
  if (!parsed) return parsed.status();
  const Json* doc = parsed->get();
  if (doc->kind != Json::Kind::Object) return bad(origin, "a costs file is one JSON object");
  const Json* format = doc->find("format");
  if (!format || format->kind != Json::Kind::String || format->text != "logrid-costs") {
    return bad(origin,
               "\"format\" is not \"logrid-costs\"; write the file with `logrid calibrate "
               "--costs FILE`");
  }
  const Json* version = doc->find("version");
  if (!version || version->kind != Json::Kind::Number || version->number != 1) {
    return bad(origin, "\"version\" is not 1, the only version this logrid reads");
  }
  CullerCostsFile file;
  if (const Json* machine = doc->find("machine")) {
    if (machine->kind == Json::Kind::String) file.machine = machine->text;
  }
  const Json* sources = doc->find("sources");
  if (!sources || sources->kind != Json::Kind::Object || sources->members.empty()) {
    return bad(origin, "\"sources\" is missing or holds no depth source");
  }
  for (const auto& [name, set] : sources->members) {
    if (set->kind != Json::Kind::Object) {
      return bad(origin, "source \"" + name + "\" is not an object");
    }
    CullerCosts costs;
    for (const CostField& f : kFields) {
      const Json* v = set->find(f.name);
      if (!v) return bad(origin, "source \"" + name + "\" has no \"" + f.name + "\"");
      if (v->kind != Json::Kind::Number) {
        return bad(origin, "source \"" + name + "\": \"" + f.name + "\" is not a number");
      }
      costs.*f.member = v->number;
    }
    const std::string problem = validateCullerCosts(costs);
    if (!problem.empty()) return bad(origin, "source \"" + name + "\": " + problem);
    file.sources[name] = costs;
  }
  return file;
}

Result<CullerCostsFile> tryLoadCullerCostsFile(const std::string& path) {
  Result<std::string> text = detail::readTextFile(path, kCostsFile);
  if (!text) return text.status();
  return tryParseCullerCosts(*text, path);
}

Result<CullerCosts> tryLoadCullerCosts(const std::string& path, const std::string& source) {
  Result<CullerCostsFile> file = tryLoadCullerCostsFile(path);
  if (!file) return file.status();
  const auto it = file->sources.find(source);
  if (it == file->sources.end()) {
    std::string names;
    for (const auto& s : file->sources) names += (names.empty() ? "" : ", ") + s.first;
    return bad(path, "no costs for depth source \"" + source + "\"; the file has " + names +
                         " (calibrate measures every source)");
  }
  return it->second;
}

std::string formatCullerCosts(const CullerCostsFile& file) {
  std::ostringstream out;
  out << "{\n  \"format\": \"logrid-costs\",\n  \"version\": 1,\n  \"machine\": \""
      << detail::jsonEscape(file.machine) << "\",\n  \"sources\": {";
  bool first_source = true;
  for (const auto& [name, costs] : file.sources) {
    out << (first_source ? "\n" : ",\n") << "    \"" << detail::jsonEscape(name) << "\": {";
    first_source = false;
    bool first = true;
    for (const CostField& f : kFields) {
      out << (first ? "" : ", ") << "\"" << f.name << "\": " << detail::jsonNumber(costs.*f.member);
      first = false;
    }
    out << "}";
  }
  out << "\n  }\n}\n";
  return out.str();
}

// ---- CostEstimate ----

namespace {

// Each term's count in a frame, in the order of kFields.
void counts(const FrameStats& f, double (&x)[CostEstimate::kTerms]) {
  x[0] = double(f.flushes);
  x[1] = double(f.pixels_read);
  x[2] = double(f.boxes_tested + f.boxes_untested);
  x[3] = double(f.triangles_drawn);
  x[4] = double(f.objects_drawn);
  x[5] = double(f.queries);
}

}  // namespace

CostEstimate::CostEstimate(const CullerCosts& prior, double decay)
    : prior_(prior), costs_(prior), decay_(decay) {}

double CostEstimate::predict(const FrameStats& frame) const {
  double x[kTerms];
  counts(frame, x);
  double y = 0;
  for (int j = 0; j < kTerms; ++j) y += x[j] * (costs_.*kFields[j].member);
  return y;
}

void CostEstimate::update(const FrameStats& frame) {
  if (!(std::isfinite(frame.seconds) && frame.seconds > 0)) return;
  // Fitted in factors of the prior: z_j = x_j * prior_j is the prior's seconds for term
  // j, and y ~ sum_j r_j z_j. Ridge toward r = 1 with a weight proportional to the
  // frames' scale, so that a term the frames barely excite keeps its prior.
  double x[kTerms], z[kTerms];
  counts(frame, x);
  for (int j = 0; j < kTerms; ++j) z[j] = x[j] * (prior_.*kFields[j].member);
  for (int j = 0; j < kTerms; ++j) {
    b_[j] = decay_ * b_[j] + z[j] * frame.seconds;
    for (int k = 0; k < kTerms; ++k) a_[j][k] = decay_ * a_[j][k] + z[j] * z[k];
  }
  ++frames_;
  double trace = 0;
  for (int j = 0; j < kTerms; ++j) trace += a_[j][j];
  if (trace <= 0) return;
  // Each term's ridge in proportion to how much the frames excited it (scale-free), and
  // a floor that keeps an unexcited term at its prior.
  double m[kTerms][kTerms + 1];
  for (int j = 0; j < kTerms; ++j) {
    const double ridge = 0.002 * a_[j][j] + 1e-6 * trace;
    for (int k = 0; k < kTerms; ++k) m[j][k] = a_[j][k] + (j == k ? ridge : 0.0);
    m[j][kTerms] = b_[j] + ridge;  // ridge * r_prior, r_prior = 1
  }
  // Gaussian elimination with partial pivoting; the ridge keeps the matrix definite.
  for (int c = 0; c < kTerms; ++c) {
    int p = c;
    for (int r = c + 1; r < kTerms; ++r) {
      if (std::fabs(m[r][c]) > std::fabs(m[p][c])) p = r;
    }
    for (int k = 0; k <= kTerms; ++k) std::swap(m[c][k], m[p][k]);
    if (std::fabs(m[c][c]) < 1e-300) return;
    for (int r = c + 1; r < kTerms; ++r) {
      const double f = m[r][c] / m[c][c];
      for (int k = c; k <= kTerms; ++k) m[r][k] -= f * m[c][k];
    }
  }
  double r[kTerms];
  for (int c = kTerms - 1; c >= 0; --c) {
    double v = m[c][kTerms];
    for (int k = c + 1; k < kTerms; ++k) v -= m[c][k] * r[k];
    r[c] = v / m[c][c];
  }
  for (int j = 0; j < kTerms; ++j) {
    const double factor = std::isfinite(r[j]) ? std::min(16.0, std::max(1.0 / 16, r[j])) : 1.0;
    costs_.*kFields[j].member = (prior_.*kFields[j].member) * factor;
  }
}

}  // namespace logrid
