// logrid view: an interactive walkthrough. A window shows the scene as `walk` renders
// it (the same FrameRunner: renderer, culler, depth readers), a fly camera or the camera
// path moves through it, and a panel shows what the culler does and changes how it
// does it, frame by frame. See README.md ("Watching the grid work") and --help.
#pragma once

#include <string>

#include "cli/options.hpp"

namespace logrid::viewer {

struct ViewerOptions {
  samples::WalkOptions walk;  // scene, view and culling options, as walk takes them
  std::string script;         // --script FILE (script.hpp)
  std::string out_dir = ".";  // screenshots and recorded camera paths
  bool play = false;          // start playing the camera path
  bool grid = false;          // start with the tile-grid overlay
  bool boxes = false;         // ... the tested boxes
  bool top_view = false;      // ... the top view
};

// Runs the viewer until the person (or the script) quits. Returns the exit code: 0, or
// 1 when a conservative configuration missed a visible object while verifying. Throws
// logrid::Error for bad options (InvalidArgument, BadInput: exit 2), no display or no
// OpenGL 4.5 (Environment, Unsupported: exit 1).
int runViewer(const ViewerOptions& options);

}  // namespace logrid::viewer
