// logrid export: writes a procedural scene as a model file (OBJ) and its walkthrough as
// a camera path (JSON), so that it can be run as a scene from a file:
//   logrid export --scene office --obj office.obj --path-json office.json
//   logrid walk --scene office.obj --path office.json ...
#include <cstdio>
#include <memory>

#include "cli/commands.hpp"
#include "cli/option_checks.hpp"
#include "logrid/error.hpp"
#include "scene/generators.hpp"
#include "scene/obj_writer.hpp"

namespace logrid::samples {
namespace {

struct ExportOptions {
  std::string scene;
  double scale = 1.0;
  std::uint64_t seed = 1;
  std::string obj;
  std::string path_json;
};

int runExport(const ExportOptions& o) {
  Scene scene;
  if (o.scene == "forest") {
    scene = makeForest({o.scale, o.seed});
  } else if (o.scene == "office") {
    scene = makeOffice({o.scale, o.seed});
  } else {
    throw Error(ErrorCode::InvalidArgument, "export: scene '" + o.scene +
                                                "' is not one that can be written; use forest or "
                                                "office");
  }
  writeObj(scene, o.obj);
  if (!o.path_json.empty()) writeCameraPathJson(scene.path, o.path_json);
  std::printf("%s: %zu triangles in %zu objects written to %s\n", scene.name.c_str(),
              scene.triangleCount(), scene.objects.size(), o.obj.c_str());
  return 0;
}

}  // namespace

void addExportCommand(CLI::App& app) {
  auto options = std::make_shared<ExportOptions>();
  CLI::App* cmd =
      app.add_subcommand("export", "write a procedural scene as an OBJ file and its path as JSON");
  cmd->add_option("--scene", options->scene, "forest or office")->required();
  addNumber(*cmd, "--scale", options->scale, above(0, kMaxForestScale),
            "scene size relative to the paper's (the office up to " +
                std::to_string(int(kMaxOfficeScale)) + ")");
  addNumber(*cmd, "--seed", options->seed, NumberRange<std::uint64_t>{}, "seed");
  cmd->add_option("--obj", options->obj, "the OBJ file to write")->required();
  cmd->add_option("--path-json", options->path_json, "the camera path JSON to write");
  cmd->final_callback([options] { throw CLI::RuntimeError(runExport(*options)); });
}

}  // namespace logrid::samples
