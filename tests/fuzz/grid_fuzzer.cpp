// libFuzzer target: the conservative projection and the lazy occlusion grid, against a
// brute-force answer.
//
// An input decodes into a camera (size, depth set-up, perspective or orthographic, eye,
// target, planes), a grid (tile size, variant) over a software depth buffer, and a
// sequence of operations: draws (a rectangle at a depth, kept only where nearer, as the
// depth test does), clears at the start of a frame and mid-frame (OcclusionGrid::fill),
// busy refreshes, refreshes of every outdated tile, and tests of boxes and of bare
// rectangles, one at a time (OcclusionGrid::test) or as batches (plan, submit, draws
// while the batch is in flight, collect, apply, resolve). The depth source is the
// software buffer itself, or an asynchronous wrapper that answers as of submit() but only
// in collect() (as GL does), reading depth or counting only (as occlusion queries do).
// For every test the grid answers Occluded, a brute-force scan of the rectangle, in the
// buffer as it was when the test's reads were submitted, must find no pixel whose key is
// at or beyond the threshold. For every box wholly in front of the
// near plane, every pixel centre inside the exact projected hull of its corners must lie
// in the projected rectangle, the box may not be called outside, and its occlusion
// threshold may not exceed the exact nearest key of its corners.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <vector>

#include "fuzz_check.hpp"
#include "logrid/camera.hpp"
#include "logrid/cpu/software_depth.hpp"
#include "logrid/error.hpp"
#include "logrid/grid.hpp"
#include "logrid/projection.hpp"

namespace {

using logrid::fuzz::Reader;

struct Window {
  double x, y, key, w;
};

// Exact (double) clip-to-window mapping of a world point.
Window toWindow(const logrid::Camera& c, const logrid::Vec3& p) {
  const double* m = c.view_projection.m;
  double clip[4];
  for (int r = 0; r < 4; ++r) {
    clip[r] = m[r] * p.x + m[4 + r] * p.y + m[8 + r] * p.z + m[12 + r];
  }
  const double w = clip[3];
  const double ndc_z = clip[2] / w;
  const double depth =
      c.depth.clip_range == logrid::ClipDepthRange::ZeroToOne ? ndc_z : 0.5 * ndc_z + 0.5;
  const double key = c.depth.convention == logrid::DepthConvention::Reversed ? -depth : depth;
  return {(clip[0] / w * 0.5 + 0.5) * c.width, (clip[1] / w * 0.5 + 0.5) * c.height, key, w};
}

// The edges of the convex hull of `pts` (counter-clockwise: every point on the left or
// on the edge), as pairs of indices; empty when the points do not span an area. An
// O(n^3) scan, done once per box: n is 8.
std::vector<std::pair<std::size_t, std::size_t>> hullEdges(const std::vector<Window>& pts) {
  std::vector<std::pair<std::size_t, std::size_t>> edges;
  const std::size_t n = pts.size();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) {
      if (i == j) continue;
      const double ex = pts[j].x - pts[i].x, ey = pts[j].y - pts[i].y;
      const double len = std::hypot(ex, ey);
      if (!(len > 1e-9)) continue;
      bool left_all = true;
      for (std::size_t k = 0; k < n && left_all; ++k) {
        left_all = ex * (pts[k].y - pts[i].y) - ey * (pts[k].x - pts[i].x) >= -1e-9 * len;
      }
      if (left_all) edges.push_back({i, j});
    }
  }
  return edges;
}

// Is (x, y) inside the hull by more than `eps` (in pixels) from every edge?
bool insideHull(const std::vector<Window>& pts,
                const std::vector<std::pair<std::size_t, std::size_t>>& edges, double x, double y,
                double eps) {
  if (edges.empty()) return false;
  for (const auto& [i, j] : edges) {
    const double ex = pts[j].x - pts[i].x, ey = pts[j].y - pts[i].y;
    if ((ex * (y - pts[i].y) - ey * (x - pts[i].x)) / std::hypot(ex, ey) <= eps) return false;
  }
  return true;
}

bool contains(const logrid::PixelRect& r, std::int32_t x, std::int32_t y) {
  return x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1;
}

// A value from the input as a window depth: mostly in [0, 1], sometimes exactly a plane,
// sometimes outside the range or not a number (what a broken application may store).
float windowDepth(Reader& in) {
  const std::uint8_t kind = in.byte();
  switch (kind % 16) {
    case 0: return 0.0f;
    case 1: return 1.0f;
    case 2: return in.anyFloat();
    default: return float(in.range(0, 1));
  }
}

logrid::PixelRect rectIn(Reader& in, std::uint32_t w, std::uint32_t h) {
  const std::int32_t x0 = std::int32_t(in.byte() % w), y0 = std::int32_t(in.byte() % h);
  const std::int32_t x1 = x0 + 1 + std::int32_t(in.byte() % (w - std::uint32_t(x0)));
  const std::int32_t y1 = y0 + 1 + std::int32_t(in.byte() % (h - std::uint32_t(y0)));
  return {x0, y0, x1, y1};
}

// An asynchronous source over the software buffer: submit() computes the answers as the
// buffer is then (a GPU's reads see the commands before them) but hands them out only in
// collect(); until then the answer array holds values that would cull everything.
class Deferred final : public logrid::DepthSource, public logrid::KeyReader {
 public:
  Deferred(logrid::cpu::SoftwareDepthBuffer& buffer, bool reads_depth)
      : buffer_(buffer), reads_depth_(reads_depth) {}
  logrid::DepthSourceTraits traits() const override {
    return {reads_depth_ ? "deferred" : "deferred-count", reads_depth_, true};
  }
  logrid::Status beginFrame(const logrid::Camera& camera) override {
    return buffer_.beginFrame(camera);
  }
  void submit(const logrid::AreaRequest* requests, std::size_t count,
              logrid::AreaAnswer* answers) override {
    for (std::size_t i = 0; i < count; ++i) {
      LOGRID_FUZZ_CHECK(reads_depth_ || requests[i].ask == logrid::AreaAsk::Count,
                        "a Summary request to a count-only source");
    }
    const std::size_t first = real_.size();
    real_.resize(first + count);
    buffer_.submit(requests, count, real_.data() + first);
    buffer_.collect();
    constexpr float kNear = -std::numeric_limits<float>::infinity();
    for (std::size_t i = 0; i < count; ++i) {
      out_.push_back(answers + i);
      answers[i] = {{kNear, kNear, 0}, 0};
    }
  }
  void collect() override {
    for (std::size_t i = 0; i < out_.size(); ++i) *out_[i] = real_[i];
    out_.clear();
    real_.clear();
  }
  void readKeys(const logrid::PixelRect& rect, float* keys) override {
    LOGRID_FUZZ_CHECK(reads_depth_, "readKeys() on a count-only source");
    buffer_.readKeys(rect, keys);
  }

 private:
  logrid::cpu::SoftwareDepthBuffer& buffer_;
  bool reads_depth_;
  std::vector<logrid::AreaAnswer> real_;
  std::vector<logrid::AreaAnswer*> out_;
};

// Keys of the buffer, a copy (the state a batch's reads saw).
std::vector<float> keysOf(const logrid::cpu::SoftwareDepthBuffer& b) {
  std::vector<float> keys(std::size_t(b.width()) * b.height());
  for (std::size_t i = 0; i < keys.size(); ++i)
    keys[i] = logrid::depthKey(b.convention(), b.data()[i]);
  return keys;
}

// An Occluded answer must find no pixel of `rect` at or beyond `threshold` in `keys`.
void checkOccluded(const logrid::OcclusionGrid& grid, const std::vector<float>& keys,
                   std::uint32_t width, const logrid::PixelRect& rect, float threshold,
                   const char* how) {
  for (std::int32_t y = rect.y0; y < rect.y1; ++y) {
    for (std::int32_t x = rect.x0; x < rect.x1; ++x) {
      const float k = keys[std::size_t(y) * width + std::size_t(x)];
      LOGRID_FUZZ_CHECK(!(k >= threshold),
                        "grid (%s, tile %u, %s) said occluded for rect [%d,%d)x[%d,%d) at "
                        "threshold %.9g, but pixel (%d, %d) has key %.9g",
                        logrid::toString(grid.desc().variant), grid.desc().tile_size, how, rect.x0,
                        rect.x1, rect.y0, rect.y1, double(threshold), x, y, double(k));
    }
  }
}

// Asks the grid one test at a time and checks an Occluded answer against the buffer.
void checkTest(logrid::OcclusionGrid& grid, logrid::cpu::SoftwareDepthBuffer& buffer,
               logrid::DepthSource& source, const logrid::PixelRect& rect, float threshold) {
  logrid::GridTestCounts counts;
  const logrid::Visibility v = grid.test(rect, threshold, source, counts);
  if (v != logrid::Visibility::Occluded) return;
  checkOccluded(grid, keysOf(buffer), buffer.width(), rect, threshold, "test");
}

// The projection against brute force, for boxes wholly in front of the near plane: not
// classed as crossing it; and, for boxes also wholly before the far plane (where the hull
// of the projected corners is exactly what the box covers, the side planes clipping at
// the viewport), every pixel centre inside that hull lies in the rectangle of an Inside
// box, and the occlusion threshold does not exceed the corners' nearest exact key.
void checkProjection(const logrid::Camera& camera, const logrid::Projector& projector,
                     const logrid::Aabb& box, const logrid::BoxProjection& p) {
  std::vector<Window> corners;
  bool in_front = true;
  double min_key = std::numeric_limits<double>::infinity();
  double max_key = -std::numeric_limits<double>::infinity();
  const double near_key = double(projector.nearKey());
  for (int c = 0; c < 8; ++c) {
    const logrid::Vec3 v{c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y,
                         c & 4 ? box.max.z : box.min.z};
    const Window wv = toWindow(camera, v);
    // In front of the near plane with room to spare.
    in_front = in_front && wv.w > 1e-6 && std::isfinite(wv.key) &&
               wv.key > near_key + 1e-6 * (1 + std::abs(near_key));
    min_key = std::min(min_key, wv.key);
    max_key = std::max(max_key, wv.key);
    corners.push_back(wv);
  }
  if (!in_front) return;
  LOGRID_FUZZ_CHECK(
      p.cls != logrid::ProjectionClass::CrossesNear && p.cls != logrid::ProjectionClass::Invalid,
      "a box in front of the near plane was classed %d", int(p.cls));
  const double clear = double(projector.clearKey());
  if (!(max_key < clear - 1e-6 * (1 + std::abs(clear)))) return;
  const auto edges = hullEdges(corners);
  for (std::uint32_t y = 0; y < camera.height; ++y) {
    for (std::uint32_t x = 0; x < camera.width; ++x) {
      // Centres inside the hull by 1e-3 pixel: rounding cannot decide those.
      if (!insideHull(corners, edges, x + 0.5, y + 0.5, 1e-3)) continue;
      LOGRID_FUZZ_CHECK(p.cls == logrid::ProjectionClass::Inside,
                        "pixel centre (%u, %u) lies inside the box's projection but the box "
                        "was classed %d",
                        x, y, int(p.cls));
      LOGRID_FUZZ_CHECK(contains(p.rect, std::int32_t(x), std::int32_t(y)),
                        "pixel centre (%u, %u) lies inside the box's projection but outside "
                        "its rect [%d,%d)x[%d,%d)",
                        x, y, p.rect.x0, p.rect.x1, p.rect.y0, p.rect.y1);
    }
  }
  if (p.cls == logrid::ProjectionClass::Inside) {
    LOGRID_FUZZ_CHECK(double(p.occlusionThreshold()) <= min_key,
                      "occlusion threshold %.9g beyond the box's nearest key %.9g",
                      double(p.occlusionThreshold()), min_key);
    LOGRID_FUZZ_CHECK(!p.rect.empty() && p.rect.x0 >= 0 && p.rect.y0 >= 0 &&
                          p.rect.x1 <= std::int32_t(camera.width) &&
                          p.rect.y1 <= std::int32_t(camera.height),
                      "rect [%d,%d)x[%d,%d) outside the %ux%u viewport", p.rect.x0, p.rect.x1,
                      p.rect.y0, p.rect.y1, camera.width, camera.height);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Reader in(data, size);
  // --- Camera ---
  logrid::Camera camera;
  camera.width = 1 + in.byte() % 48;
  camera.height = 1 + in.byte() % 48;
  const std::uint8_t setup = in.byte();
  const bool reversed = setup & 1;
  camera.depth.convention =
      reversed ? logrid::DepthConvention::Reversed : logrid::DepthConvention::Standard;
  camera.depth.clip_range = reversed || (setup & 2) ? logrid::ClipDepthRange::ZeroToOne
                                                    : logrid::ClipDepthRange::NegativeOneToOne;
  camera.depth.format = (setup >> 2) % 3 == 0   ? logrid::DepthFormat::D16
                        : (setup >> 2) % 3 == 1 ? logrid::DepthFormat::D24
                                                : logrid::DepthFormat::D32F;
  camera.multisample = setup & 0x40;
  const bool ortho = setup & 0x80;
  const logrid::DVec3 eye{in.range(-20, 20), in.range(-20, 20), in.range(-20, 20)};
  const logrid::DVec3 target{in.range(-5, 5), in.range(-5, 5), in.range(-5, 5)};
  const double near_plane = in.range(0.01, 5);
  const std::uint8_t far_choice = in.byte();
  double far_plane = near_plane * (1.5 + in.range(0, 1000));
  if (reversed && !ortho && far_choice % 4 == 0)
    far_plane = std::numeric_limits<double>::infinity();
  const double aspect = double(camera.width) / double(camera.height);
  try {
    const logrid::Mat4d view = logrid::lookAt(eye, target, {0, 1, 0});
    const logrid::Mat4d projection =
        ortho
            ? logrid::orthographic(-10 * aspect, 10 * aspect, -10, 10, near_plane, far_plane,
                                   camera.depth)
            : logrid::perspective(in.range(0.2, 3.0), aspect, near_plane, far_plane, camera.depth);
    camera.view_projection = logrid::multiply(projection, view);
  } catch (const logrid::Error&) {
    return 0;  // eye == target or up parallel to the view: lookAt refuses, as documented
  }
  if (!logrid::validateCamera(camera).empty()) return 0;
  const logrid::Projector projector(camera);

  // --- Grid, buffer and source ---
  logrid::GridDesc desc;
  desc.width = camera.width;
  desc.height = camera.height;
  desc.tile_size = 1 + in.byte() % 64;
  desc.variant = in.byte() & 1 ? logrid::GridVariant::Zfar : logrid::GridVariant::OcclusionState;
  logrid::OcclusionGrid grid(desc);
  logrid::cpu::SoftwareDepthBuffer buffer(camera.width, camera.height, camera.depth.convention);
  const std::uint8_t source_kind = in.byte() % 3;
  Deferred deferred(buffer, source_kind == 1);
  logrid::DepthSource& source = source_kind == 0 ? static_cast<logrid::DepthSource&>(buffer)
                                                 : static_cast<logrid::DepthSource&>(deferred);
  if (!source.beginFrame(camera)) std::abort();  // the camera is valid: it cannot fail
  buffer.clear();
  grid.reset(projector.clearKey());
  const bool state = desc.variant == logrid::GridVariant::OcclusionState;
  const std::uint32_t w = camera.width, h = camera.height;

  // A box from the input: its projection checked by brute force, and the test the
  // culler would make of it (nullopt when the projection decides alone).
  struct Asked {
    logrid::PixelRect rect;
    float threshold;
  };
  auto boxTest = [&]() -> std::optional<Asked> {
    logrid::Vec3 lo{float(in.range(-15, 15)), float(in.range(-15, 15)), float(in.range(-15, 15))};
    const logrid::Vec3 hi{lo.x + float(in.range(0, 8)), lo.y + float(in.range(0, 8)),
                          lo.z + float(in.range(0, 8))};
    const logrid::BoxProjection p = projector.project({lo, hi});
    checkProjection(camera, projector, {lo, hi}, p);
    if (p.cls != logrid::ProjectionClass::Inside) return std::nullopt;
    return Asked{p.rect, state ? projector.clearKey() : p.occlusionThreshold()};
  };
  // A bare rectangle; the zfar grid takes any threshold.
  auto rectTest = [&]() -> Asked {
    const logrid::PixelRect r = rectIn(in, w, h);
    return {r, state ? projector.clearKey() : float(in.range(-1.1, 1.1))};
  };
  auto draw = [&]() {
    const logrid::PixelRect r = rectIn(in, w, h);
    buffer.fillRect(r, windowDepth(in));
    grid.markOutdated(r);
  };

  // --- Operations ---
  for (int op = 0; op < 64 && in.left() > 0; ++op) {
    switch (in.byte() % 9) {
      case 0:
      case 1: draw(); break;
      case 2:  // a new frame
        buffer.clear();
        grid.reset(projector.clearKey());
        break;
      case 3: {  // a mid-frame clear, to the clear key or a nearer value
        const float k =
            in.byte() & 1
                ? projector.clearKey()
                : float(in.range(double(projector.nearKey()), double(projector.clearKey())));
        const float d = logrid::windowDepth(camera.depth.convention, k);
        for (std::size_t i = 0; i < std::size_t(w) * h; ++i) buffer.data()[i] = d;
        // The buffer holds d; its key may round away from k: fill with the stored key.
        grid.fill(logrid::depthKey(camera.depth.convention, d));
        break;
      }
      case 4: grid.refreshNow(rectIn(in, w, h), source); break;
      case 5: {
        logrid::GridTestCounts counts;
        grid.refreshOutdated(source, counts);
        break;
      }
      case 6: {
        const Asked a = rectTest();
        checkTest(grid, buffer, source, a.rect, a.threshold);
        break;
      }
      case 7: {
        if (const std::optional<Asked> a = boxTest()) {
          checkTest(grid, buffer, source, a->rect, a->threshold);
        }
        break;
      }
      default: {  // a batch: plan, submit, draw while it is in flight, collect, resolve
        logrid::GridBatch batch;
        std::vector<Asked> batched;
        const std::vector<float> planned = keysOf(buffer);
        const int tests = 1 + in.byte() % 8;
        for (int t = 0; t < tests; ++t) {
          std::optional<Asked> a = in.byte() & 1 ? boxTest() : std::optional<Asked>(rectTest());
          if (!a) continue;
          logrid::GridTestCounts counts;
          const std::optional<logrid::Visibility> now =
              grid.plan(a->rect, a->threshold, source.traits(), &batch, counts);
          if (!now) {
            batched.push_back(*a);
          } else if (*now == logrid::Visibility::Occluded) {
            checkOccluded(grid, planned, w, a->rect, a->threshold, "plan");
          }
        }
        LOGRID_FUZZ_CHECK(batch.tests() == batched.size(), "batch holds %zu tests, %zu planned",
                          batch.tests(), batched.size());
        grid.submit(batch, source);
        const int draws = in.byte() % 4;
        for (int d = 0; d < draws; ++d) draw();
        source.collect();
        grid.apply(batch);
        for (std::size_t i = 0; i < batched.size(); ++i) {
          logrid::GridTestCounts counts;
          if (grid.resolve(batch, i) == logrid::Visibility::Occluded) {
            checkOccluded(grid, planned, w, batched[i].rect, batched[i].threshold, "batch");
          }
        }
        break;
      }
    }
  }
  return 0;
}
