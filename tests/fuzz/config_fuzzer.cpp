// libFuzzer target: the core's two JSON files, the culler configuration (parseCullerConfig,
// logrid/config.hpp; what `logrid tune --auto --write-config` writes) and the costs file
// (parseCullerCosts, logrid/costs.hpp; what `logrid calibrate --costs` writes), each given
// the whole input. For each, every input must either be refused with a
// logrid::Error(BadInput) whose message names the file, or read into a value that the
// library's own validation accepts (validateCullerDesc, validateCullerCosts: no NaN, no
// value out of range, the settings the file does not hold left at their defaults) and that
// the writer (formatCullerConfig, formatCullerCosts) turns into text reading back to the
// same value.
#include <cmath>
#include <exception>
#include <string>

#include "fuzz_check.hpp"
#include "logrid/config.hpp"
#include "logrid/costs.hpp"
#include "logrid/culler.hpp"
#include "logrid/error.hpp"

namespace {

const std::string kOrigin = "fuzz_input.json";

// A refusal: BadInput, naming the file first.
void checkRefusal(const logrid::Error& e, const char* parser) {
  const std::string what = e.what();
  LOGRID_FUZZ_CHECK(e.code() == logrid::ErrorCode::BadInput, "%s: unexpected error code %d: %s",
                    parser, int(e.code()), e.what());
  LOGRID_FUZZ_CHECK(
      what.size() > kOrigin.size() + 2 && what.compare(0, kOrigin.size(), kOrigin) == 0,
      "%s: the error does not name the file first: %s", parser, e.what());
}

bool sameCosts(const logrid::CullerCosts& a, const logrid::CullerCosts& b) {
  return a.flush_s == b.flush_s && a.pixel_s == b.pixel_s && a.box_test_s == b.box_test_s &&
         a.triangle_s == b.triangle_s && a.draw_s == b.draw_s && a.query_s == b.query_s;
}

bool sameConfig(const logrid::CullerConfig& a, const logrid::CullerConfig& b) {
  const logrid::CullerDesc& x = a.culler;
  const logrid::CullerDesc& y = b.culler;
  return a.source == b.source && x.method == y.method && x.tile_size == y.tile_size &&
         x.lookahead == y.lookahead && x.temporal_coherence == y.temporal_coherence &&
         x.detect_colliding == y.detect_colliding &&
         x.approximation.visible_pixels == y.approximation.visible_pixels &&
         x.approximation.full_free_fraction == y.approximation.full_free_fraction &&
         x.approximation.row_stride == y.approximation.row_stride;
}

void checkConfig(const std::string& text) {
  logrid::CullerConfig config;
  try {
    config = logrid::parseCullerConfig(text, kOrigin);
  } catch (const logrid::Error& e) {
    checkRefusal(e, "parseCullerConfig");
    return;
  } catch (const std::exception& e) {
    LOGRID_FUZZ_CHECK(false, "parseCullerConfig: not a logrid::Error: %s", e.what());
  }
  const logrid::CullerDesc& d = config.culler;
  const std::string problem = logrid::validateCullerDesc(d);
  LOGRID_FUZZ_CHECK(problem.empty(), "parseCullerConfig accepted an invalid culler: %s",
                    problem.c_str());
  const float fraction = d.approximation.full_free_fraction;
  LOGRID_FUZZ_CHECK(std::isfinite(fraction) && fraction >= 0 && fraction <= 1 && d.tile_size >= 1 &&
                        d.lookahead >= 1 && d.approximation.row_stride >= 1,
                    "accepted full_free_fraction %.9g, tile_size %u, lookahead %u, row_stride %u",
                    double(fraction), d.tile_size, d.lookahead, d.approximation.row_stride);
  // What the file does not hold stays as CullerDesc has it.
  const logrid::CullerDesc defaults;
  LOGRID_FUZZ_CHECK(d.budget_ms == defaults.budget_ms && sameCosts(d.costs, defaults.costs),
                    "the configuration set a budget (%g ms) or costs it does not hold",
                    d.budget_ms);
  const std::string written = logrid::formatCullerConfig(config);
  logrid::CullerConfig back;
  try {
    back = logrid::parseCullerConfig(written, "written");
  } catch (const logrid::Error& e) {
    LOGRID_FUZZ_CHECK(false, "what formatCullerConfig wrote is refused: %s\n%s", e.what(),
                      written.c_str());
  }
  LOGRID_FUZZ_CHECK(sameConfig(config, back), "the configuration changed on a write and read:\n%s",
                    written.c_str());
}

void checkCosts(const std::string& text) {
  logrid::CullerCostsFile file;
  try {
    file = logrid::parseCullerCosts(text, kOrigin);
  } catch (const logrid::Error& e) {
    checkRefusal(e, "parseCullerCosts");
    return;
  } catch (const std::exception& e) {
    LOGRID_FUZZ_CHECK(false, "parseCullerCosts: not a logrid::Error: %s", e.what());
  }
  LOGRID_FUZZ_CHECK(!file.sources.empty(), "a costs file without sources was accepted");
  for (const auto& [name, costs] : file.sources) {
    const std::string problem = logrid::validateCullerCosts(costs);
    LOGRID_FUZZ_CHECK(problem.empty(), "source \"%s\": accepted invalid costs: %s", name.c_str(),
                      problem.c_str());
    for (double v : {costs.flush_s, costs.pixel_s, costs.box_test_s, costs.triangle_s, costs.draw_s,
                     costs.query_s}) {
      LOGRID_FUZZ_CHECK(std::isfinite(v) && v > 0 && v <= 1, "source \"%s\": accepted cost %.17g",
                        name.c_str(), v);
    }
  }
  const std::string written = logrid::formatCullerCosts(file);
  logrid::CullerCostsFile back;
  try {
    back = logrid::parseCullerCosts(written, "written");
  } catch (const logrid::Error& e) {
    LOGRID_FUZZ_CHECK(false, "what formatCullerCosts wrote is refused: %s\n%s", e.what(),
                      written.c_str());
  }
  LOGRID_FUZZ_CHECK(back.machine == file.machine, "the machine changed on a write and read:\n%s",
                    written.c_str());
  LOGRID_FUZZ_CHECK(back.sources.size() == file.sources.size(), "%zu sources read back as %zu:\n%s",
                    file.sources.size(), back.sources.size(), written.c_str());
  for (const auto& [name, costs] : file.sources) {
    const auto it = back.sources.find(name);
    LOGRID_FUZZ_CHECK(it != back.sources.end() && sameCosts(it->second, costs),
                      "source \"%s\" changed on a write and read:\n%s", name.c_str(),
                      written.c_str());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  checkConfig(text);
  checkCosts(text);
  return 0;
}
