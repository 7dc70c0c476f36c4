// A scene ready to walk through: generated or loaded, prepared (hierarchy, renderer's
// mesh), uploaded to GL, with its DDO octree when a method needs one, and what each step
// took in time and memory.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "cli/options.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "scene/ddo_scene.hpp"
#include "scene/prepare.hpp"

namespace logrid::samples {

struct LoadedScene {
  PreparedScene prepared;
  std::unique_ptr<gl::MeshRenderer> renderer;
  std::optional<DdoScene> ddo;               // when a method needs it (then also prepared.ddo)
  double generate_ms = 0;                    // generating or loading
  std::uint64_t peak_rss_bytes = 0;          // after uploading to GL
  std::uint64_t prepare_peak_rss_bytes = 0;  // after generating and preparing, before GL
  nlohmann::json describe() const;
};

// The options of `base` for one scene of a multi-scene command: its name, and
// forest_scale / city_scale for the procedural scenes when > 0.
WalkOptions optionsForScene(const WalkOptions& base, const std::string& scene, double forest_scale,
                            double city_scale);

// Creates (or loads) the scene named by the options and, with `upload`, uploads it
// (needs a context then). With `with_ddo`, also builds or loads its DDO octree.
LoadedScene loadScene(const WalkOptions& o, bool upload = true, bool with_ddo = false);

// The DDO options the walkthrough options ask for (the file resolved).
DdoOptions ddoOptions(const WalkOptions& o);
nlohmann::json describeDdo(const DdoScene& d);

}  // namespace logrid::samples
