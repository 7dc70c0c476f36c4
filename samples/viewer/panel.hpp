// The viewer's panel (Dear ImGui): live and one-second numbers of the frame, the culling
// controls, the views, path playback and recording; and the F1 help.
#pragma once

#include <cstddef>
#include <string>

#include "viewer/frame_stats.hpp"
#include "viewer/settings.hpp"

namespace logrid::viewer {

struct PanelModel {
  // Edited by the panel; the viewer applies them before the next frame.
  CullSettings* settings = nullptr;
  DisplaySettings* display = nullptr;
  // Shown.
  const RollingStats* stats = nullptr;
  std::string scene;            // "forest: 1,570,402 triangles, 5,672 objects"
  std::string renderer;         // GL renderer and version
  std::string message;          // the last thing done (screenshot written, ...)
  std::string error;            // the last change that could not be made
  std::size_t frame_count = 0;  // walk's --frames: the path's frames
  double path_frame = 0;        // where playback is, in those frames
  bool playing = false;
  bool recording = false;
  double record_seconds = 0;
  double speed = 0;  // fly speed, units per second
  std::size_t verified_frames = 0, missed_total = 0, frames_with_misses = 0;
  // Asked for by the panel this frame.
  bool screenshot = false;
  bool toggle_record = false;
  bool toggle_play = false;
  int step = 0;  // path frames to step (pauses)
};

void drawPanel(PanelModel& model);
// The keys and mouse controls, as a window; `open` is cleared when closed.
void drawHelp(bool* open);

}  // namespace logrid::viewer
