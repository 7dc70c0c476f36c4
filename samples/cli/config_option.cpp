#include "cli/config_option.hpp"

#include <nlohmann/json.hpp>

#include <fstream>
#include <limits>
#include <sstream>

#include "cli/frame_runner.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {
namespace {

// The options a configuration file sets; none may be given beside --config.
constexpr const char* kConfigured[] = {
    "--method",         "--tile",          "--tiles",     "--reader",     "--lookahead",
    "--coherence",      "--colliding",     "--leaf",      "--tree-parts", "--cluster",
    "--visible-pixels", "--full-fraction", "--row-stride"};

[[noreturn]] void badScene(const std::string& path, const std::string& what) {
  throw Error(ErrorCode::BadInput, path + ": \"scene\": " + what);
}

// The "scene" section (the library ignores it): box granularity.
void applySceneSection(const std::string& path, WalkOptions& o) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  // loadCullerConfig has read it as JSON already.
  const nlohmann::json doc = nlohmann::json::parse(text.str(), nullptr, false);
  if (!doc.is_object() || !doc.contains("scene")) return;
  const nlohmann::json& scene = doc["scene"];
  if (!scene.is_object()) badScene(path, "is not an object");
  if (scene.contains("leaf")) {
    const nlohmann::json& leaf = scene["leaf"];
    if (!leaf.is_number_unsigned() ||
        leaf.get<std::uint64_t>() > std::numeric_limits<std::uint32_t>::max()) {
      badScene(path, "\"leaf\" is not a whole number in [0, 4294967295] (0: the scene's default)");
    }
    o.leaf = leaf.get<std::uint32_t>();
  }
  if (scene.contains("cluster")) {
    const nlohmann::json& cluster = scene["cluster"];
    if (!cluster.is_number_unsigned() || cluster.get<std::uint64_t>() > 512) {
      badScene(path, "\"cluster\" is not a whole number in [0, 512] (0: whole objects)");
    }
    o.cluster = cluster.get<std::uint32_t>();
  }
  if (scene.contains("tree_parts")) {
    if (!scene["tree_parts"].is_string()) badScene(path, "\"tree_parts\" is not a name");
    o.tree_parts = scene["tree_parts"].get<std::string>();
  }
}

}  // namespace

ConfigSettings applyConfigFile(const std::string& path, const WalkOptions& base) {
  const CullerConfig config = loadCullerConfig(path);
  const CullerDesc& d = config.culler;
  const MethodTakes& takes = methodInfo(d.method).takes;
  ConfigSettings out;
  MethodChoice choice(d.method);
  if (takes.lookahead) choice.lookahead = d.lookahead;
  choice.coherence = takes.temporal_coherence && d.temporal_coherence;
  out.method = choice.name();
  out.options = base;
  WalkOptions& o = out.options;
  o.method = out.method;
  o.tile = d.tile_size;
  if (!config.source.empty()) o.reader = config.source;
  o.colliding = d.detect_colliding;
  o.approximation = d.approximation;
  applySceneSection(path, o);
  return out;
}

std::string sceneSection(const WalkOptions& o) {
  return nlohmann::json{{"leaf", o.leaf}, {"tree_parts", o.tree_parts}, {"cluster", o.cluster}}
      .dump();
}

CLI::Option* addConfigOption(CLI::App& app, WalkOptions& o,
                             std::function<void(const std::string& method)> use_method) {
  CLI::Option* config = app.add_option_function<std::string>(
      "--config",
      [&o, use_method](const std::string& path) {
        ConfigSettings s = applyConfigFile(path, o);
        o = std::move(s.options);
        if (use_method) use_method(s.method);
      },
      "a configuration file of `logrid tune --auto --write-config FILE`: its method, "
      "lookahead, coherence, tile size, depth reader and box granularity in place of those "
      "options");
  for (const char* name : kConfigured) {
    if (CLI::Option* other = app.get_option_no_throw(name)) config->excludes(other);
  }
  return config;
}

}  // namespace logrid::samples
