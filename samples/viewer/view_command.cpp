// logrid view: the command line of the interactive viewer (viewer.hpp).
#include <memory>

#include "cli/commands.hpp"
#include "cli/config_option.hpp"
#include "cli/frame_runner.hpp"
#include "cli/options.hpp"
#include "cli/readers.hpp"
#include "logrid/method.hpp"
#include "viewer/viewer.hpp"

namespace logrid::samples {

void addViewCommand(CLI::App& app) {
  auto o = std::make_shared<viewer::ViewerOptions>();
  CLI::App* view = app.add_subcommand(
      "view", "fly through a scene in a window and watch the culling (needs a display; F1: keys)");
  addSceneOptions(*view, o->walk);
  view->add_option("--method", o->walk.method, samples::methodChoiceHelp());
  addSizeOption(*view, o->walk.size, "initial window size");
  addViewOptions(*view, o->walk);
  view->add_flag("--verify", o->walk.verify,
                 "check every frame against the object-ID oracle; missed objects flash red");
  view->add_flag("--grid", o->grid, "start with the tile-grid overlay (G)");
  view->add_flag("--boxes", o->boxes, "start with the tested boxes shown (B)");
  view->add_flag("--top-view", o->top_view, "start with the view from above (T)");
  view->add_flag("--play", o->play, "start playing the camera path (Space)");
  view->add_option("--script", o->script,
                   "drive the viewer from a file of input events, one per line: 'FRAME key W', "
                   "'FRAME mouse-move X Y', ... (samples/viewer/script.hpp); ends after its last "
                   "event");
  view->add_option("--out", o->out_dir, "folder for screenshots and recorded paths (default .)");
  addConfigOption(*view, o->walk);
  view->final_callback([o] { throw CLI::RuntimeError(viewer::runViewer(*o)); });
}

}  // namespace logrid::samples
