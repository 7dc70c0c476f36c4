#include "viewer/top_view.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "logrid/glm_camera.hpp"
#include "logrid/projection.hpp"

namespace logrid::viewer {
namespace {

double dot(const glm::dvec3& a, double x, double y, double z) {
  return a.x * x + a.y * y + a.z * z;
}

enum : std::uint8_t { kOutside, kOccluded, kDrawn, kMissed };

const ImU32 kColors[4] = {IM_COL32(90, 90, 90, 255), IM_COL32(200, 60, 50, 255),
                          IM_COL32(60, 200, 80, 255), IM_COL32(255, 40, 220, 255)};

}  // namespace

void TopView::setFootprint(std::size_t i, const Aabb& b) {
  const double c[3] = {0.5 * (double(b.min.x) + b.max.x), 0.5 * (double(b.min.y) + b.max.y),
                       0.5 * (double(b.min.z) + b.max.z)};
  const double h[3] = {0.5 * (double(b.max.x) - b.min.x), 0.5 * (double(b.max.y) - b.min.y),
                       0.5 * (double(b.max.z) - b.min.z)};
  const glm::dvec3* axes[2] = {&east_, &north_};
  for (int k = 0; k < 2; ++k) {
    const glm::dvec3& a = *axes[k];
    const double mid = dot(a, c[0], c[1], c[2]);
    const double half = std::fabs(a.x) * h[0] + std::fabs(a.y) * h[1] + std::fabs(a.z) * h[2];
    rects_[i * 4 + std::size_t(k)] = float(mid - half);
    rects_[i * 4 + 2 + std::size_t(k)] = float(mid + half);
  }
}

TopView::TopView(const samples::PreparedScene& scene, const FlyCamera& camera)
    : scene_(scene), east_(camera.east()), north_(camera.north()) {
  const std::size_t n = scene.object_boxes.size();
  rects_.resize(n * 4);
  lo_[0] = lo_[1] = INFINITY;
  hi_[0] = hi_[1] = -INFINITY;
  for (std::size_t i = 0; i < n; ++i) {
    setFootprint(i, scene.object_boxes[i]);
    // The view's extent is the static scene's: movers that leave it are clipped.
    if (i >= scene.static_objects) continue;
    for (std::size_t k = 0; k < 2; ++k) {
      const float lo = rects_[i * 4 + k], hi = rects_[i * 4 + 2 + k];
      if (std::isfinite(lo) && std::isfinite(hi)) {
        lo_[k] = std::min(lo_[k], lo);
        hi_[k] = std::max(hi_[k], hi);
      }
    }
  }
  if (!(lo_[0] < hi_[0]) || !(lo_[1] < hi_[1])) lo_[0] = lo_[1] = 0, hi_[0] = hi_[1] = 1;
  if (!scene.path.empty()) {
    const double t0 = scene.path.keys().front().time, d = scene.path.duration();
    for (int i = 0; i <= 200; ++i) {
      const samples::CameraPose p = scene.path.at(t0 + d * i / 200.0);
      const double x = p.position.x - scene.origin.x, y = p.position.y - scene.origin.y,
                   z = p.position.z - scene.origin.z;
      path_.push_back(float(dot(east_, x, y, z)));
      path_.push_back(float(dot(north_, x, y, z)));
    }
  }
  state_.resize(n);
  order_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) order_[i] = i;
  auto area = [&](std::uint32_t i) {
    const float* r = &rects_[std::size_t(i) * 4];
    return double(r[2] - r[0]) * double(r[3] - r[1]);
  };
  std::stable_sort(order_.begin(), order_.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return area(a) > area(b); });
}

// The view's coordinates (east, north of the scene's origin) on the canvas: the static
// scene's extent fitted into it with a margin, north up.
struct TopView::Canvas {
  ImDrawList* dl;
  glm::dvec3 east, north;
  float lo[2];
  float ox, oy, scale;

  ImVec2 at(double e, double n) const {
    return ImVec2(ox + float(e - lo[0]) * scale, oy - float(n - lo[1]) * scale);
  }
  // A point relative to the scene's origin.
  ImVec2 atLocal(double x, double y, double z) const {
    return at(dot(east, x, y, z), dot(north, x, y, z));
  }
};

TopView::Counts TopView::draw(const Frame& f, bool* open) {
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowSize(ImVec2(300, 320), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 310, io.DisplaySize.y - 330),
                          ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Top view", open)) {
    ImGui::End();
    return {};
  }
  ImGui::TextColored(ImColor(kColors[kDrawn]), "drawn");
  ImGui::SameLine();
  ImGui::TextColored(ImColor(kColors[kOccluded]), "occluded");
  ImGui::SameLine();
  ImGui::TextColored(ImColor(kColors[kOutside]), "outside");
  ImGui::SameLine();
  ImGui::TextColored(ImColor(kColors[kMissed]), "missed");
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImVec2 size = ImGui::GetContentRegionAvail();
  size.x = std::max(size.x, 32.0f);
  size.y = std::max(size.y, 32.0f);
  ImGui::InvisibleButton("top_view_canvas", size);
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->PushClipRect(p0, ImVec2(p0.x + size.x, p0.y + size.y), true);
  dl->AddRectFilled(p0, ImVec2(p0.x + size.x, p0.y + size.y), IM_COL32(20, 22, 28, 255));

  const float margin = 6;
  const float scale = std::min((size.x - 2 * margin) / (hi_[0] - lo_[0]),
                               (size.y - 2 * margin) / (hi_[1] - lo_[1]));
  const Canvas canvas{dl,
                      east_,
                      north_,
                      {lo_[0], lo_[1]},
                      p0.x + 0.5f * (size.x - scale * (hi_[0] - lo_[0])),
                      p0.y + 0.5f * (size.y + scale * (hi_[1] - lo_[1])),
                      scale};
  classify(f);
  drawFootprints(canvas, f.flash);
  drawPaths(canvas, f.recorded);
  if (f.camera) drawCamera(canvas, *f.camera);
  dl->PopClipRect();
  ImGui::End();
  Counts counts;
  for (std::uint8_t s : state_) {
    counts.drawn += s == kDrawn;
    counts.occluded += s == kOccluded;
    counts.outside += s == kOutside;
    counts.missed += s == kMissed;
  }
  return counts;
}

void TopView::classify(const Frame& f) {
  const std::size_t n = scene_.object_boxes.size();
  // Movers where they are this frame (the static objects' footprints never change).
  const std::vector<Aabb>& boxes = f.boxes && f.boxes->size() == n ? *f.boxes : scene_.object_boxes;
  for (std::size_t i = scene_.static_objects; i < n; ++i) setFootprint(i, boxes[i]);
  std::fill(state_.begin(), state_.end(), kOutside);
  if (!f.camera) return;
  const Projector projector(*f.camera);
  for (std::size_t i = 0; i < n; ++i) {
    if (projector.project(boxes[i]).cls != ProjectionClass::Outside) state_[i] = kOccluded;
  }
  if (f.drawn) {
    for (ObjectId id : *f.drawn) state_[id] = kDrawn;
  }
  if (f.missed) {
    for (ObjectId id : *f.missed) state_[id] = kMissed;
  }
}

void TopView::drawFootprints(const Canvas& canvas, bool flash) const {
  // Largest footprints first (terrain under trees), so that every object shows.
  for (std::uint32_t i : order_) {
    const float* r = &rects_[std::size_t(i) * 4];
    ImVec2 a = canvas.at(r[0], r[3]), b = canvas.at(r[2], r[1]);
    b.x = std::max(b.x, a.x + 1);  // at least a pixel
    b.y = std::max(b.y, a.y + 1);
    const std::uint8_t s = state_[i];
    canvas.dl->AddRectFilled(a, b,
                             s == kMissed && !flash ? IM_COL32(255, 255, 255, 255) : kColors[s]);
    if (b.x - a.x > 6 && b.y - a.y > 6) canvas.dl->AddRect(a, b, IM_COL32(0, 0, 0, 120));
  }
}

void TopView::drawPaths(const Canvas& canvas, const std::vector<glm::dvec3>* recorded) const {
  for (std::size_t i = 2; i + 1 < path_.size(); i += 2) {
    canvas.dl->AddLine(canvas.at(path_[i - 2], path_[i - 1]), canvas.at(path_[i], path_[i + 1]),
                       IM_COL32(120, 170, 255, 160));
  }
  if (!recorded) return;
  const glm::dvec3& o = scene_.origin;
  for (std::size_t i = 1; i < recorded->size(); ++i) {
    const glm::dvec3& a = (*recorded)[i - 1];
    const glm::dvec3& b = (*recorded)[i];
    canvas.dl->AddLine(canvas.atLocal(a.x - o.x, a.y - o.y, a.z - o.z),
                       canvas.atLocal(b.x - o.x, b.y - o.y, b.z - o.z), IM_COL32(255, 160, 40, 255),
                       2);
  }
}

void TopView::drawCamera(const Canvas& canvas, const Camera& camera) const {
  // The frustum: its eight corners from clip space back to the scene's coordinates.
  const glm::dmat4 view_projection = toGlm(camera.view_projection);
  if (std::fabs(glm::determinant(view_projection)) > 0) {
    const glm::dmat4 inverse = glm::inverse(view_projection);
    const double z_near = camera.depth.clip_range == ClipDepthRange::ZeroToOne ? 0 : -1;
    ImVec2 corner[8];
    bool ok = true;
    for (int i = 0; i < 8; ++i) {
      const glm::dvec4 p = inverse * glm::dvec4((i & 1) ? 1.0 : -1.0, (i & 2) ? 1.0 : -1.0,
                                                (i & 4) ? 1.0 : z_near, 1.0);
      ok = ok && std::fabs(p.w) > 1e-12;
      if (ok) corner[i] = canvas.atLocal(p.x / p.w, p.y / p.w, p.z / p.w);
    }
    if (ok) {
      static const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                       {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
      for (const auto& e : edges) {
        canvas.dl->AddLine(corner[e[0]], corner[e[1]], IM_COL32(255, 230, 60, 255), 1.5f);
      }
    }
  }
  const DVec3& eye = camera.render_origin;  // the eye, in the scene's coordinates
  canvas.dl->AddCircleFilled(canvas.atLocal(eye.x, eye.y, eye.z), 4, IM_COL32(255, 255, 255, 255));
}

}  // namespace logrid::viewer
