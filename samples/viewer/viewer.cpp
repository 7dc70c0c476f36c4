#include "viewer/viewer.hpp"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <thread>

#include "cli/common.hpp"
#include "cli/images.hpp"
#include "cli/loaded_scene.hpp"
#include "cli/machine.hpp"
#include "cli/readers.hpp"
#include "cli/report.hpp"
#include "cli/values.hpp"
#include "logrid/elapsed.hpp"
#include "logrid/error.hpp"
#include "logrid/projection.hpp"
#include "scene/view.hpp"
#include "viewer/fly_camera.hpp"
#include "viewer/frame_stats.hpp"
#include "viewer/imgui_layer.hpp"
#include "viewer/panel.hpp"
#include "viewer/script.hpp"
#include "viewer/settings.hpp"
#include "viewer/top_view.hpp"
#include "viewer/window.hpp"

namespace logrid::viewer {
namespace {

// Playback shows walk's frames (--frames spread over the path) at this rate.
constexpr double kPathFramesPerSecond = 30;
// A recorded flight keeps a camera key this often (viewer time), and the last pose.
constexpr double kRecordInterval = 0.1;
// Longest viewer step: after a stall the camera does not jump across the scene.
constexpr double kMaxStepSeconds = 0.25;

void say(const std::string& line) {
  std::printf("view: %s\n", line.c_str());
  std::fflush(stdout);
}

std::string withCommas(std::uint64_t v) {
  std::string digits = std::to_string(v), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

// DIR/PREFIX0001.EXT, the first that does not exist yet.
std::string freshName(const std::string& dir, const char* prefix, const char* ext) {
  for (int i = 1;; ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "%s%04d%s", prefix, i, ext);
    const std::filesystem::path p = std::filesystem::path(dir) / name;
    if (!std::filesystem::exists(p) || i >= 9999) return p.string();
  }
}

bool compatible(const std::string& method, const std::string& reader) {
  const auto m = parseMethod(method);
  const samples::ReaderInfo* r = samples::findReader(reader);
  return !m || !r || !methodInfo(*m).needs.depth_values || r->reads_depth;
}

// Shows a frame in the window: the runner's framebuffer blitted, or a picture (an
// overlay) uploaded into a texture and blitted.
class Presenter {
 public:
  ~Presenter() { release(); }
  void blit(std::uint32_t framebuffer, std::uint32_t w, std::uint32_t h) {
    glDisable(GL_SCISSOR_TEST);
    glBlitNamedFramebuffer(framebuffer, 0, 0, 0, GLint(w), GLint(h), 0, 0, GLint(w), GLint(h),
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
  void image(const std::vector<std::uint8_t>& rgba, std::uint32_t w, std::uint32_t h) {
    if (w != w_ || h != h_) {
      release();
      glCreateTextures(GL_TEXTURE_2D, 1, &texture_);
      glTextureStorage2D(texture_, 1, GL_RGBA8, GLsizei(w), GLsizei(h));
      glCreateFramebuffers(1, &fbo_);
      glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, texture_, 0);
      w_ = w;
      h_ = h;
    }
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glTextureSubImage2D(texture_, 0, 0, 0, GLsizei(w), GLsizei(h), GL_RGBA, GL_UNSIGNED_BYTE,
                        rgba.data());
    blit(fbo_, w, h);
  }

 private:
  void release() {
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    if (texture_) glDeleteTextures(1, &texture_);
    fbo_ = texture_ = 0;
    w_ = h_ = 0;
  }
  GLuint texture_ = 0, fbo_ = 0;
  std::uint32_t w_ = 0, h_ = 0;
};

class Viewer {
 public:
  Viewer(const ViewerOptions& o, std::optional<Script> script)
      : options_(o), script_(std::move(script)) {
    const auto [w, h] = samples::parseSize(o.walk.size);
    WindowDesc desc;
    desc.width = w;
    desc.height = h;
    desc.title = "logrid view: " + o.walk.scene;
#ifndef NDEBUG
    desc.debug = true;
#endif
    desc.vsync = !script_;
    window_ = std::make_unique<Window>(desc);
    // The DDO octree only when the first method needs it (its preprocessing is long).
    scene_ = samples::loadScene(o.walk, true, samples::needsDdo(o.walk.method));
    base_ = samples::runConfig(o.walk, scene_.prepared);
    settings_ = settingsOf(base_);
    applied_ = settings_;
    display_.grid = o.grid;
    display_.boxes = o.boxes;
    display_.top_view = o.top_view;
    playing_ = o.play;
    const samples::PreparedScene& p = scene_.prepared;
    const double dx = double(p.bounds.max.x) - p.bounds.min.x,
                 dy = double(p.bounds.max.y) - p.bounds.min.y,
                 dz = double(p.bounds.max.z) - p.bounds.min.z;
    const double diagonal = std::sqrt(dx * dx + dy * dy + dz * dz);
    fly_.emplace(poseAt(0), std::isfinite(diagonal) && diagonal > 0 ? diagonal / 20 : 1.0);
    top_view_.emplace(p, *fly_);
    ui_ = std::make_unique<ImGuiLayer>();
    renderer_name_ = window_->glRenderer();
    scene_line_ = p.name + ": " + withCommas(p.triangles) + " triangles, " +
                  withCommas(p.mesh.draws.size()) + " objects";
    say("window " + renderer_name_);
    say("scene " + scene_line_);
  }

  int run() {
    auto last = std::chrono::steady_clock::now();
    for (;; ++frame_) {
      const auto start = std::chrono::steady_clock::now();
      double dt = std::chrono::duration<double>(start - last).count();
      last = start;
      dt = script_ ? kScriptedFrameSeconds : std::clamp(dt, 1e-4, kMaxStepSeconds);
      clock_ += dt;
      gatherInput();
      if (input_.quit() || window_->closeRequested()) break;
      const auto [fw, fh] = window_->framebufferSize();
      const auto [ww, wh] = window_->windowSize();
      ui_->newFrame(ww, wh, fw, fh, input_, dt);
      if (!ui_->wantsKeyboard()) handleKeys();
      if (quit_) {
        ImGui::EndFrame();
        break;
      }
      updateCamera(dt);
      const bool ready = applySettings(fw, fh);
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      glViewport(0, 0, GLsizei(fw), GLsizei(fh));
      glDisable(GL_SCISSOR_TEST);
      glClearColor(0.08f, 0.08f, 0.1f, 1);
      glClear(GL_COLOR_BUFFER_BIT);
      std::optional<samples::FrameRecord> record;
      if (ready && fw > 0 && fh > 0) record = renderFrame(fw, fh);
      if (!ready && !script_) std::this_thread::sleep_for(std::chrono::milliseconds(20));
      drawUi(fw, fh, ww, wh);
      ui_->render();
      if (screenshot_) screenshot(fw, fh);
      if (recording_ && clock_ - recorded_.back().time - record_start_ >= kRecordInterval) {
        addKey();
      }
      window_->swap();
      gl::checkGlErrors("view: frame");
      if (record) {
        stats_.add(FrameSample::of(*record, clock_, msSince(start)));
        ++frames_drawn_;
      }
      if (script_ && frame_ >= script_->lastFrame()) break;
    }
    if (recording_) finishRecording();
    std::string summary = std::to_string(frames_drawn_) + " frames drawn";
    if (verified_frames_ > 0) {
      summary += "; verify: " + std::to_string(verified_frames_) + " frames checked, " +
                 std::to_string(missed_total_) + " visible objects missed (" +
                 std::to_string(missed_exact_) + " by exact settings)";
    }
    say(summary);
    if (missed_exact_ > 0) {
      std::fprintf(stderr,
                   "view: a conservative method missed visible objects: it must never do that; "
                   "please report it with the command line and a recorded path (R)\n");
      return 1;
    }
    return 0;
  }

 private:
  samples::CameraPose poseAt(double path_frame) const {
    const samples::CameraPath& path = scene_.prepared.path;
    const std::size_t frames = base_.frames;
    if (path.empty()) return path.at(0);  // throws the empty-path error
    const double t0 = path.keys().front().time;
    if (frames < 2) return path.at(t0);
    return path.at(t0 + path.duration() * std::clamp(path_frame / double(frames - 1), 0.0, 1.0));
  }

  void gatherInput() {
    std::vector<InputEvent> events;
    window_->poll(events);
    if (script_) {
      // Only closing the window counts: the script is the person.
      events.erase(std::remove_if(events.begin(), events.end(),
                                  [](const InputEvent& e) { return e.type != EventType::Quit; }),
                   events.end());
      for (const InputEvent& e : script_->eventsAt(frame_)) events.push_back(e);
    }
    input_.beginFrame();
    for (const InputEvent& e : events) input_.apply(e);
    if (const auto size = input_.resize()) window_->requestSize(size->first, size->second);
  }

  void toggle(bool& flag, const char* what) {
    flag = !flag;
    message_ = std::string(what) + (flag ? " on" : " off");
    say(message_);
  }

  void handleKeys() {
    const bool shift = input_.shift();
    for (int key : input_.pressedKeys()) {
      switch (key) {
        case GLFW_KEY_ESCAPE: quit_ = true; break;
        case GLFW_KEY_F1: display_.help = !display_.help; break;
        case GLFW_KEY_F12:
        case GLFW_KEY_P: screenshot_ = true; break;
        case GLFW_KEY_R: toggleRecording(); break;
        case GLFW_KEY_SPACE: playing_ = !playing_; break;
        case GLFW_KEY_PERIOD: step(1); break;
        case GLFW_KEY_COMMA: step(-1); break;
        case GLFW_KEY_M: {
          // The next method the reader can serve (so that M never gets stuck).
          const std::vector<std::string> methods = methodChoices();
          std::string m = settings_.method;
          for (std::size_t i = 0; i < methods.size(); ++i) {
            m = cycle(methods, m, shift ? -1 : 1);
            if (compatible(m, settings_.reader)) break;
          }
          settings_.method = m;
          break;
        }
        case GLFW_KEY_N: {
          const std::vector<std::string> readers = readerChoices();
          std::string r = settings_.reader;
          for (std::size_t i = 0; i < readers.size(); ++i) {
            r = cycle(readers, r, shift ? -1 : 1);
            if (compatible(settings_.method, r)) break;
          }
          settings_.reader = r;
          break;
        }
        case GLFW_KEY_G: toggle(display_.grid, "tile grid"); break;
        case GLFW_KEY_B: toggle(display_.boxes, "tested boxes"); break;
        case GLFW_KEY_T: toggle(display_.top_view, "top view"); break;
        case GLFW_KEY_V: toggle(settings_.verify, "verify"); break;
        case GLFW_KEY_TAB: display_.panel = !display_.panel; break;
        default: break;
      }
    }
  }

  void step(int frames) {
    playing_ = false;
    const double last = double(std::max<std::size_t>(base_.frames, 1) - 1);
    path_frame_ = std::clamp(std::round(path_frame_) + frames, 0.0, last);
    fly_->setPose(poseAt(path_frame_));
  }

  void updateCamera(double dt) {
    const bool ui_mouse = ui_->wantsMouse();
    for (int b : {GLFW_MOUSE_BUTTON_RIGHT, GLFW_MOUSE_BUTTON_LEFT}) {
      if (!look_button_ && input_.buttonPressed(b) && !ui_mouse) {
        look_button_ = b;
        if (!script_) window_->captureCursor(true);
      }
    }
    bool moved = false;
    if (look_button_) {
      if (input_.motionX() != 0 || input_.motionY() != 0) {
        fly_->look(input_.motionX(), input_.motionY());
        moved = true;
      }
      if (!input_.buttonDown(*look_button_)) {
        look_button_.reset();
        if (!script_) window_->captureCursor(false);
      }
    }
    if (!ui_mouse && input_.scroll() != 0) fly_->scaleSpeed(input_.scroll());
    if (!ui_->wantsKeyboard()) {
      auto axis = [&](int plus, int plus2, int minus, int minus2) {
        return double(input_.down(plus) || input_.down(plus2)) -
               double(input_.down(minus) || input_.down(minus2));
      };
      const double f = axis(GLFW_KEY_W, GLFW_KEY_UP, GLFW_KEY_S, GLFW_KEY_DOWN);
      const double r = axis(GLFW_KEY_D, GLFW_KEY_RIGHT, GLFW_KEY_A, GLFW_KEY_LEFT);
      const double u = axis(GLFW_KEY_E, GLFW_KEY_PAGE_UP, GLFW_KEY_Q, GLFW_KEY_PAGE_DOWN);
      if (f != 0 || r != 0 || u != 0) {
        const double boost = input_.shift() ? 4.0 : input_.control() ? 0.25 : 1.0;
        fly_->move(f, r, u, dt * boost);
        moved = true;
      }
    }
    if (moved) playing_ = false;  // the person takes over
    if (playing_) {
      const double frames = double(std::max<std::size_t>(base_.frames, 1));
      path_frame_ += dt * kPathFramesPerSecond;
      if (path_frame_ > frames - 1) path_frame_ = 0;  // loop
      fly_->setPose(poseAt(path_frame_));
    }
  }

  // Rebuilds the runner when the settings or the drawable's size changed. False when
  // there is nothing to draw with.
  bool applySettings(std::uint32_t w, std::uint32_t h) {
    if (w == 0 || h == 0) return false;  // minimised
    const bool same_size =
        runner_ && runner_->config().view.width == w && runner_->config().view.height == h;
    if (runner_ && same_size && settings_ == applied_) return true;
    if (failed_ && failed_->first == settings_ && failed_->second == std::make_pair(w, h)) {
      settings_ = applied_;
      return runner_ && same_size;
    }
    try {
      auto next = std::make_unique<samples::FrameRunner>(scene_.prepared, *scene_.renderer,
                                                         configFor(base_, settings_, w, h));
      const bool changed = !runner_ || settings_ != applied_;
      runner_ = std::move(next);
      applied_ = settings_;
      error_.clear();
      failed_.reset();
      if (changed) {
        stats_.clear();
        say(describe(settings_));
      }
      if (!same_size) say("drawable " + std::to_string(w) + "x" + std::to_string(h));
      return true;
    } catch (const Error& e) {
      if (!runner_) throw;  // nothing to show at all
      failed_ = std::make_pair(settings_, std::make_pair(w, h));
      error_ = e.what();
      std::fprintf(stderr, "view: %s (kept: %s)\n", e.what(), describe(applied_).c_str());
      settings_ = applied_;
      return same_size;
    }
  }

  samples::FrameRecord renderFrame(std::uint32_t w, std::uint32_t h) {
    const samples::CameraPose pose = fly_->pose();
    camera_ = runner_->cameraAt(pose);
    samples::FrameRecord rec = runner_->renderPose(pose, frame_);
    if (rec.missed >= 0) {
      ++verified_frames_;
      missed_total_ += std::size_t(rec.missed);
      frames_with_misses_ += rec.missed > 0;
      if (effectiveApproximation(applied_.method, applied_.approximation).exact()) {
        missed_exact_ += std::size_t(rec.missed);
      }
      if (rec.missed > 0) {
        say("frame " + std::to_string(frame_) + ": " + std::to_string(rec.missed) +
            " visible objects not drawn (first: " + std::to_string(rec.missed_ids.front()) + ")");
      }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, GLsizei(w), GLsizei(h));
    if (display_.grid || display_.boxes) {
      samples::OverlayData data = runner_->overlayData();
      if (!display_.grid) data.grid = nullptr;
      if (!display_.boxes) {
        data.occluded.clear();
        data.tested_visible.clear();
        data.drawn_boxes.clear();
      }
      data.shade = shadeFor(display_.shade, applied_.method);
      data.outline_visible = display_.boxes;
      presenter_.image(samples::drawOverlay(runner_->readColor(), camera_, data), w, h);
    } else {
      presenter_.blit(runner_->framebuffer().handle(), w, h);
    }
    return rec;
  }

  void drawUi(std::uint32_t fw, std::uint32_t fh, std::uint32_t ww, std::uint32_t wh) {
    const bool flash = std::fmod(clock_, 0.5) < 0.3;
    if (runner_ && !runner_->missedObjects().empty() && ww > 0 && wh > 0) {
      // Missed objects: their pixel rectangles, blinking red over the frame.
      const float sx = float(ww) / float(fw), sy = float(wh) / float(fh);
      ImDrawList* dl = ImGui::GetBackgroundDrawList();
      const Projector projector(camera_);
      for (ObjectId id : runner_->missedObjects()) {
        const PixelRect r = projector.project(scene_.prepared.object_boxes[id]).rect;
        const ImVec2 a(float(r.x0) * sx, float(std::int64_t(fh) - r.y1) * sy);
        const ImVec2 b(float(r.x1) * sx, float(std::int64_t(fh) - r.y0) * sy);
        if (flash) dl->AddRectFilled(a, b, IM_COL32(255, 30, 30, 150));
        dl->AddRect(a, b, IM_COL32(255, 30, 30, 255), 0, 0, 2);
      }
    }
    if (display_.panel) {
      PanelModel m;
      m.settings = &settings_;
      m.display = &display_;
      m.stats = &stats_;
      m.scene = scene_line_;
      m.renderer = renderer_name_;
      m.message = message_;
      m.error = error_;
      m.frame_count = base_.frames;
      m.path_frame = path_frame_;
      m.playing = playing_;
      m.recording = recording_;
      m.record_seconds = recording_ ? clock_ - record_start_ : 0;
      m.speed = fly_->speed();
      m.verified_frames = verified_frames_;
      m.missed_total = missed_total_;
      m.frames_with_misses = frames_with_misses_;
      drawPanel(m);
      if (m.screenshot) screenshot_ = true;
      if (m.toggle_record) toggleRecording();
      if (m.toggle_play) playing_ = !playing_;
      if (m.step) step(m.step);
    }
    if (display_.top_view) {
      TopView::Frame f;
      f.camera = runner_ ? &camera_ : nullptr;
      f.boxes = runner_ ? &runner_->objectBoxes() : nullptr;
      f.drawn = runner_ ? &runner_->drawnObjects() : nullptr;
      f.missed = runner_ ? &runner_->missedObjects() : nullptr;
      f.recorded = recording_ ? &recorded_positions_ : nullptr;
      f.flash = flash;
      top_view_->draw(f, &display_.top_view);
    }
    if (display_.help) drawHelp(&display_.help);
  }

  void screenshot(std::uint32_t w, std::uint32_t h) {
    screenshot_ = false;
    if (w == 0 || h == 0) return;
    std::vector<std::uint8_t> rgba = window_->readBackBuffer();
    for (std::size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255;  // a picture is opaque
    const std::string file = freshName(options_.out_dir, "logrid_view_", ".png");
    try {
      samples::writePng(file, rgba, w, h);
      message_ = "screenshot " + file;
      say(message_ + " (" + std::to_string(w) + "x" + std::to_string(h) + ")");
    } catch (const Error& e) {
      error_ = e.what();
      std::fprintf(stderr, "view: %s\n", e.what());
    }
  }

  void addKey() {
    const samples::CameraPose pose = fly_->pose();
    const double t = clock_ - record_start_;
    if (!recorded_.empty() && !(t > recorded_.back().time)) return;
    recorded_.push_back({pose.position, pose.look_at, t});
    recorded_positions_.push_back(pose.position);
  }

  void toggleRecording() {
    if (recording_) {
      finishRecording();
      return;
    }
    recording_ = true;
    recorded_.clear();
    recorded_positions_.clear();
    record_start_ = clock_;
    addKey();
    message_ = "recording the flight (R stops)";
    say("recording");
  }

  void finishRecording() {
    recording_ = false;
    addKey();
    const std::string file = freshName(options_.out_dir, "logrid_path_", ".json");
    try {
      const samples::CameraPath path(recorded_, fly_->up());
      samples::writeText(file, path.toJsonText());
      char seconds[32];
      std::snprintf(seconds, sizeof seconds, "%.2f", path.duration());
      message_ = "recorded " + file;
      say("recorded " + file + " (" + std::to_string(recorded_.size()) + " keys, " + seconds +
          " s); replay: logrid walk --scene " + options_.walk.scene + " --path " + file);
    } catch (const Error& e) {
      error_ = e.what();
      std::fprintf(stderr, "view: %s\n", e.what());
    }
  }

  const ViewerOptions& options_;
  std::optional<Script> script_;
  std::unique_ptr<Window> window_;  // first made, last destroyed: the context
  samples::LoadedScene scene_;
  samples::RunConfig base_;
  std::unique_ptr<ImGuiLayer> ui_;
  Presenter presenter_;
  std::unique_ptr<samples::FrameRunner> runner_;
  std::optional<FlyCamera> fly_;
  std::optional<TopView> top_view_;
  InputState input_;
  CullSettings settings_, applied_;
  std::optional<std::pair<CullSettings, std::pair<std::uint32_t, std::uint32_t>>> failed_;
  DisplaySettings display_;
  RollingStats stats_;
  Camera camera_;
  std::string renderer_name_, scene_line_, message_, error_;
  std::size_t frame_ = 0;  // viewer frames (the script's numbers)
  std::size_t frames_drawn_ = 0;
  double clock_ = 0;
  bool quit_ = false;
  bool screenshot_ = false;
  bool playing_ = false;
  double path_frame_ = 0;
  std::optional<int> look_button_;
  bool recording_ = false;
  double record_start_ = 0;
  std::vector<samples::CameraKey> recorded_;
  std::vector<glm::dvec3> recorded_positions_;
  std::size_t verified_frames_ = 0, missed_total_ = 0, frames_with_misses_ = 0, missed_exact_ = 0;
};

}  // namespace

int runViewer(const ViewerOptions& options) {
  // Everything that can be checked without a window is checked first (exit 2 at once).
  std::optional<Script> script;
  if (!options.script.empty()) script = Script::fromFile(options.script);
  {
    samples::WalkOptions check = options.walk;
    check.near_plane = check.far_plane = 0;  // the scene's planes are not known yet
    samples::runConfig(check, samples::PreparedScene{});
  }
  samples::contextDesc(options.walk);  // the platform name, and LP_NUM_THREADS
  std::error_code ec;
  std::filesystem::create_directories(options.out_dir, ec);
  if (ec || !std::filesystem::is_directory(options.out_dir)) {
    throw Error(ErrorCode::Environment, "view: cannot create the output folder '" +
                                            options.out_dir + "' (" + ec.message() +
                                            "); pass a writable folder with --out");
  }
  Viewer viewer(options, std::move(script));
  return viewer.run();
}

}  // namespace logrid::viewer
