#include "cli/experiment.hpp"

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>

#include "cli/common.hpp"
#include "cli/machine.hpp"
#include "cli/report.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {

std::vector<Variant> combine(const std::vector<Axis>& axes) {
  std::vector<Variant> out{{"", [](WalkOptions&) {}}};
  for (const Axis& axis : axes) {
    std::vector<Variant> next;
    for (const Variant& outer : out) {
      for (const Variant& inner : axis) {
        const std::string space = outer.label.empty() || inner.label.empty() ? "" : " ";
        next.push_back(
            {outer.label + space + inner.label, [a = outer.apply, b = inner.apply](WalkOptions& o) {
               a(o);
               b(o);
             }});
      }
    }
    out = std::move(next);
  }
  return out;
}

std::string methodFamily(const RunConfig& config) {
  MethodChoice base = config.method;  // the name without traversal settings
  base.lookahead.reset();
  base.coherence = false;
  return base.name();
}

std::vector<PlotPanel> familyPanels(
    const std::vector<Measured>& measured,
    const std::function<std::optional<PlotSeries>(const Measured&)>& series,
    const std::optional<PlotSeries>& floor) {
  std::vector<std::string> families;
  std::vector<std::vector<PlotSeries>> members;
  for (const Measured& m : measured) {
    std::optional<PlotSeries> s = series(m);
    if (!s) continue;
    const std::string family = methodFamily(m.result.config);
    const auto at = std::find(families.begin(), families.end(), family);
    if (at == families.end()) {
      families.push_back(family);
      members.push_back({std::move(*s)});
    } else {
      members[std::size_t(at - families.begin())].push_back(std::move(*s));
    }
  }
  std::vector<PlotPanel> panels;
  PlotPanel others{"other methods", {}};
  std::size_t single_families = 0;
  for (std::size_t f = 0; f < families.size(); ++f) {
    if (members[f].size() > 1) {
      panels.push_back({families[f], std::move(members[f])});
    } else {
      ++single_families;
      others.title = single_families == 1 ? families[f] : "other methods";
      others.series.push_back(std::move(members[f].front()));
    }
  }
  if (!others.series.empty()) panels.push_back(std::move(others));
  if (floor) {
    for (PlotPanel& p : panels) p.series.push_back(*floor);
  }
  return panels;
}

Experiment::Experiment(const ExperimentOptions& options, const std::string& name,
                       const std::string& title, const std::string& intro)
    : options_(options) {
  if (options_.scenes.empty() || options_.sizes.empty()) {
    throw Error(ErrorCode::InvalidArgument, name + ": --scenes and --sizes need an entry");
  }
  if (!options_.plots.empty()) std::filesystem::create_directories(options_.plots);
  context_ = std::make_unique<gl::Context>(contextDesc(options_.walk));
  const nlohmann::json machine = machineInfo(*context_);
  std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  md_ << "# " << title << "\n\nMachine: " << machineLine(machine) << ". " << date
      << ".\n\nCommand: `" << commandLine() << "`\n\n"
      << intro;
  report_ = {{"command", commandLine()},
             {"machine", machine},
             {"date", date},
             {"repeat", options_.repeat}};
}

Experiment::~Experiment() = default;

WalkOptions Experiment::sceneOptions(const std::string& scene) const {
  return optionsForScene(options_.walk, scene, options_.forest_scale, options_.city_scale);
}

LoadedScene Experiment::load(const WalkOptions& scene_options,
                             const std::vector<Variant>& variants) const {
  bool with_ddo = false;
  for (const Variant& v : variants) {
    WalkOptions o = scene_options;
    v.apply(o);
    with_ddo = with_ddo || needsDdo(o.method);
  }
  return loadScene(scene_options, true, with_ddo);
}

std::vector<Measured> Experiment::run(const LoadedScene& scene, const WalkOptions& cell,
                                      const std::vector<Variant>& variants,
                                      const std::string& progress_label) const {
  std::vector<RunConfig> configs;
  for (const Variant& v : variants) {
    WalkOptions o = cell;
    o.verify = options_.verify;
    v.apply(o);
    configs.push_back(runConfig(o, scene.prepared));
  }
  std::vector<ConfigResult> results = runInterleaved(
      scene.prepared, *scene.renderer, configs, options_.repeat, progress_label, options_.warmup);
  std::vector<Measured> out;
  for (std::size_t c = 0; c < results.size(); ++c) {
    const FrameAverages frames = averageFrames(results[c].records);
    out.push_back({variants[c].label, std::move(results[c]), frames});
  }
  return out;
}

std::string Experiment::plotStem(const std::string& name) const {
  return options_.plots.empty() ? "" : options_.plots + "/" + name;
}

std::string Experiment::plotImage(const std::string& alt, const std::string& name) const {
  if (options_.plots.empty() || options_.markdown.empty()) return "";
  return "![" + alt + "](" + linkFrom(options_.markdown, plotStem(name) + ".png") + ")";
}

int Experiment::finish(const std::string& failure) {
  std::printf("%s", md_.str().c_str());
  if (!options_.markdown.empty()) writeText(options_.markdown, md_.str());
  if (!options_.json.empty()) writeJson(options_.json, report_);
  if (failure.empty()) return 0;
  std::fprintf(stderr, "%s\n", failure.c_str());
  return 1;
}

}  // namespace logrid::samples
