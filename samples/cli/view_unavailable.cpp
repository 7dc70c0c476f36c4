// logrid view in a build without the viewer (GLFW or Dear ImGui were not found when
// CMake configured, or LOGRID_BUILD_VIEWER was off): the command exists and says how to
// get it.
#include <cstdio>

#include "cli/commands.hpp"

namespace logrid::samples {

void addViewCommand(CLI::App& app) {
  CLI::App* view = app.add_subcommand(
      "view", "fly through a scene in a window (not in this build: see its message)");
  view->allow_extras();
  view->final_callback([] {
    std::fprintf(stderr,
                 "logrid: this logrid was built without the viewer: CMake did not find GLFW "
                 "3.3 and Dear ImGui, or was told -DLOGRID_BUILD_VIEWER=OFF. On Debian 12: "
                 "apt-get install libglfw3-dev libimgui-dev libstb-dev (scripts/setup.sh "
                 "installs them), then configure with -DLOGRID_BUILD_VIEWER=ON and build "
                 "again.\n");
    throw CLI::RuntimeError(1);
  });
}

}  // namespace logrid::samples
