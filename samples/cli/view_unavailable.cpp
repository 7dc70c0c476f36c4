// logrid view in a build without the viewer (GLFW or Dear ImGui were not found when
// CMake configured): the command exists and says how to get it.
#include <cstdio>

#include "cli/commands.hpp"

namespace logrid::samples {

void addViewCommand(CLI::App& app) {
  CLI::App* view = app.add_subcommand(
      "view", "fly through a scene in a window (not in this build: see its message)");
  view->allow_extras();
  view->final_callback([] {
    std::fprintf(stderr,
                 "logrid: this logrid was built without the viewer: GLFW and Dear ImGui were "
                 "not found when CMake configured (LOGRID_BUILD_VIEWER). On Debian 12: "
                 "apt-get install libglfw3-dev libimgui-dev libstb-dev, then configure and "
                 "build again (scripts/setup.sh installs them).\n");
    throw CLI::RuntimeError(1);
  });
}

}  // namespace logrid::samples
