// Scripted input for `logrid view --script FILE`: what a person would do, frame by
// frame, so that the viewer can be driven (and tested) without one.
//
// One event per line, `FRAME EVENT ARGUMENTS`; '#' starts a comment; blank lines are
// skipped. Frames count from 0 and must not decrease; the events of frame F are applied
// before frame F is drawn, in the order written. The session ends (exit 0) after the
// frame of the last event, unless a key quits it earlier (Escape).
//
//   F key NAME                 press NAME at F, release it at F + 1
//   F key-down NAME            hold NAME from F ...
//   F key-up NAME              ... until here
//   F mouse-move X Y           cursor to window coordinates (origin top-left)
//   F mouse-down BUTTON        left, right or middle
//   F mouse-up BUTTON
//   F click BUTTON X Y         move to X Y, press at F, release at F + 1
//   F drag BUTTON DX DY N      press at F, move by (DX, DY) over N frames, release at F + N + 1
//   F scroll STEPS             mouse wheel (positive: away from the user)
//   F text "STRING"            type text into the focused field of the panel
//   F resize W H               ask the window system for a window of W x H
//
// Key names are keyNameList()'s (case-insensitive). With a script the viewer's clock
// advances by a fixed step per frame (ScriptedClock below), so a flight is the same on
// every machine, and input from the window system other than closing it is ignored.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "viewer/input.hpp"

namespace logrid::viewer {

// Seconds of viewer time per frame under a script.
inline constexpr double kScriptedFrameSeconds = 1.0 / 30.0;

struct ScriptEvent {
  std::size_t frame = 0;
  InputEvent event;
};

class Script {
 public:
  // Throws logrid::Error(BadInput) naming the file, the line and what is wrong, or
  // (Environment) when the file cannot be read.
  static Script fromFile(const std::string& path);
  static Script fromText(const std::string& text, const std::string& name = "<script>");

  // The events of `frame`, in order.
  std::vector<InputEvent> eventsAt(std::size_t frame) const;
  // The frame after which the session ends.
  std::size_t lastFrame() const { return last_frame_; }
  const std::vector<ScriptEvent>& events() const { return events_; }

 private:
  std::vector<ScriptEvent> events_;  // sorted by frame, stable
  std::size_t last_frame_ = 0;
};

}  // namespace logrid::viewer
