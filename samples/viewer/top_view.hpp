// The view from above: every object's footprint coloured by what the culler did with it
// this frame (drawn, occluded, outside the frustum, or visible but missed), the camera's
// frustum and the camera path, moving objects where they are in the frame. Drawn with
// Dear ImGui into its own panel window.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/camera.hpp"
#include "scene/prepare.hpp"
#include "viewer/fly_camera.hpp"

namespace logrid::viewer {

class TopView {
 public:
  // The footprints are taken once, along the fly camera's horizontal axes.
  TopView(const samples::PreparedScene& scene, const FlyCamera& camera);

  struct Frame {
    const Camera* camera = nullptr;  // this frame's (nullptr: none drawn)
    // Every object's box this frame (movers where they are); nullptr: the scene's boxes.
    const std::vector<Aabb>* boxes = nullptr;
    const std::vector<ObjectId>* drawn = nullptr;
    const std::vector<ObjectId>* missed = nullptr;
    const std::vector<glm::dvec3>* recorded = nullptr;  // world positions being recorded
    bool flash = false;                                 // missed objects' blink phase
  };
  // Counts of the last draw() (for the panel and tests).
  struct Counts {
    std::size_t drawn = 0, occluded = 0, outside = 0, missed = 0;
  };
  // An ImGui window; `open` is cleared when the person closes it.
  Counts draw(const Frame& frame, bool* open);

 private:
  struct Canvas;  // where the view's coordinates land in the window
  // Object i's footprint from its box `b`, into rects_.
  void setFootprint(std::size_t i, const Aabb& b);
  // draw()'s steps: each object's state this frame into state_ (movers' footprints
  // moved); the footprints in their states' colours; the scene's path and the recorded
  // one; the camera's frustum and eye.
  void classify(const Frame& frame);
  void drawFootprints(const Canvas& canvas, bool flash) const;
  void drawPaths(const Canvas& canvas, const std::vector<glm::dvec3>* recorded) const;
  void drawCamera(const Canvas& canvas, const Camera& camera) const;

  const samples::PreparedScene& scene_;
  glm::dvec3 east_, north_;
  std::vector<float> rects_;  // per object: east min, north min, east max, north max (local)
  float lo_[2] = {0, 0}, hi_[2] = {1, 1};
  std::vector<float> path_;           // the scene's camera path, sampled, local (east, north) pairs
  std::vector<std::uint32_t> order_;  // objects by footprint, largest first
  std::vector<std::uint8_t> state_;
};

}  // namespace logrid::viewer
