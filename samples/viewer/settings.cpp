#include "viewer/settings.hpp"

#include <algorithm>
#include <sstream>

#include "cli/readers.hpp"
#include "logrid/error.hpp"
#include "logrid/query_schedule.hpp"
#include "scene/view.hpp"

namespace logrid::viewer {

bool CullSettings::operator==(const CullSettings& o) const {
  return method == o.method && reader == o.reader && tile == o.tile && format == o.format &&
         convention == o.convention && lookahead == o.lookahead && coherence == o.coherence &&
         approximation.visible_pixels == o.approximation.visible_pixels &&
         approximation.full_free_fraction == o.approximation.full_free_fraction &&
         approximation.row_stride == o.approximation.row_stride && verify == o.verify;
}

GridApproximation effectiveApproximation(const std::string& method, const GridApproximation& a) {
  const auto m = parseMethod(method);
  GridApproximation out;
  if (!m) return out;
  const MethodInfo& info = methodInfo(*m);
  if (info.takes.visible_pixels) out.visible_pixels = a.visible_pixels;
  if (info.takes.full_fraction) out.full_free_fraction = a.full_free_fraction;
  if (info.takes.row_stride) out.row_stride = a.row_stride;
  return out;
}

CullSettings settingsOf(const samples::RunConfig& config) {
  CullSettings s;
  s.method = config.method.name();
  s.reader = config.reader;
  s.tile = config.culler.tile_size;
  s.format = config.view.depth.format;
  s.convention = config.view.depth.convention;
  s.lookahead = config.culler.lookahead;
  s.coherence = config.culler.temporal_coherence;
  s.approximation = config.culler.approximation;
  s.verify = config.verify;
  return s;
}

samples::RunConfig configFor(const samples::RunConfig& base, const CullSettings& s,
                             std::uint32_t width, std::uint32_t height) {
  samples::RunConfig c = base;
  std::string problem;
  const auto method = samples::parseMethodChoice(s.method, &problem);
  if (!method) throw Error(ErrorCode::InvalidArgument, problem);
  c.method = *method;
  c.reader = s.reader;
  c.culler.tile_size = s.tile;
  c.culler.lookahead = s.lookahead;
  c.culler.temporal_coherence = s.coherence;
  c.culler.approximation = effectiveApproximation(s.method, s.approximation);
  c.view.depth = samples::depthSetupFor(s.convention, s.format);
  c.view.width = width;
  c.view.height = height;
  c.verify = s.verify;
  c.overlay = true;  // record what the overlays draw
  c.images_dir.clear();
  if (c.method.method) {
    CullerDesc check = c.culler;
    check.method = *c.method.method;
    // Unmeasured hardware parameters are no problem here: the frame runner measures
    // them on its context (measureHardwareIfNeeded) before nohc runs; check the rest.
    if (!validateHardwareParameters(check.queries.hardware).empty()) {
      check.queries.hardware.render_setup = check.queries.hardware.query_setup = 1;
    }
    problem = validateCullerDesc(check);
    if (!problem.empty()) throw Error(ErrorCode::InvalidArgument, problem);
  }
  return c;
}

std::string describe(const CullSettings& s) {
  std::ostringstream out;
  out << "method " << s.method << ", reader " << s.reader << ", tile " << s.tile << ", depth "
      << toString(s.format) << " " << toString(s.convention) << ", lookahead ";
  if (s.lookahead == kUnlimitedLookahead) {
    out << "all";
  } else {
    out << s.lookahead;
  }
  out << ", coherence " << (s.coherence ? "on" : "off") << ", verify " << (s.verify ? "on" : "off");
  const GridApproximation a = effectiveApproximation(s.method, s.approximation);
  if (a.exact()) {
    out << ", exact";
  } else {
    out << ", approximate (visible pixels " << a.visible_pixels << ", full fraction "
        << a.full_free_fraction << ", row stride " << a.row_stride << ")";
  }
  return out.str();
}

std::vector<std::string> methodChoices() {
  std::vector<std::string> out;
  for (const MethodInfo& m : methodTable()) out.push_back(m.name);
  out.push_back("oracle");
  return out;
}

std::vector<std::string> readerChoices() {
  std::vector<std::string> out;
  for (const samples::ReaderInfo& r : samples::readerTable()) out.push_back(r.name);
  return out;
}

std::string cycle(const std::vector<std::string>& list, const std::string& current, int step) {
  if (list.empty()) return current;
  const auto it = std::find(list.begin(), list.end(), current);
  const long n = long(list.size());
  const long i = it == list.end() ? 0 : long(it - list.begin());
  return list[std::size_t(((i + step) % n + n) % n)];
}

samples::TileShade shadeFor(ShadeChoice choice, const std::string& method) {
  switch (choice) {
    case ShadeChoice::States: return samples::TileShade::States;
    case ShadeChoice::Zfar: return samples::TileShade::Zfar;
    case ShadeChoice::Auto: break;
  }
  const auto m = parseMethod(method);
  return m && methodInfo(*m).semantics != TestSemantics::OcclusionState
             ? samples::TileShade::Zfar
             : samples::TileShade::States;
}

}  // namespace logrid::viewer
