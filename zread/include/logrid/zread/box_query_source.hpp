// Hardware occlusion queries over an OpenGL framebuffer's depth buffer: the
// OcclusionQueries (occlusion_queries.hpp) that logrid's query methods (hwq, chc, stat,
// nohc, log+hwq) issue their queries through. Needs a current GL 4.5 context and the
// framebuffer the application draws into (0: the default one).
//
//   issueBoxes  draws the faces of each QueryBox (12 triangles, front and back faces, one
//               instanced draw for up to 64 boxes) with the depth test of the camera's
//               convention keeping the nearer-or-equal fragment (GL_LEQUAL standard,
//               GL_GEQUAL reversed), every write off, and each vertex's clip z moved by the
//               box's depth bias (QueryBox::depth_bias, converted to the clip range), so
//               that the faces lie nearer than any geometry inside the box. The vertex
//               transform is the one a camera-relative renderer uses (as MeshRenderer):
//               the matrix view_projection * translation(render_origin rounded to float)
//               in float, applied to corner - render_origin; Projector's margins bound its
//               rounding (projection.hpp).
//   issueRects  a scissored full-viewport triangle per rectangle whose fragments all get
//               the rectangle's threshold depth (gl_FragDepth), rounded so that a pixel
//               stored exactly at the threshold passes.
// One GL query object per query, of `target`: GL_SAMPLES_PASSED (counts, the default) or
// GL_ANY_SAMPLES_PASSED_CONSERVATIVE (0 or 1; may answer 1 where nothing passes; cheaper
// on some GPUs). Objects are pooled and reused frame to frame.
//
// The query pass does not depend on the application's GL state: each issue sets what it
// draws with through a GlStateGuard scope (gl_state.hpp: the neutral raster state of
// prepareDraw(), the camera's clip control, its own program and vertex array) and restores
// the application's state before it returns. Conditional rendering, unpaused transform
// feedback and a GL error pending from the application are refused with an error (the
// query answers "visible"; OcclusionQueries, "a call below that fails").
//
// Flushes: a poll or result after new commands (an issue, or a draw the culler announced
// with noteDraw) makes the driver start that work (on Mesa llvmpipe: rasterise the
// pending scene); QueryCounters::flushes counts such calls.
//
// beginQueryFrame() checks the framebuffer's depth attachment against Camera::depth.format
// and returns an error if they differ (or if the source's programs could not be made).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "logrid/occlusion_queries.hpp"
#include "logrid/zread/gl_state.hpp"
#include "logrid/zread/program.hpp"

namespace logrid::zread {

enum class QueryTarget : std::uint8_t {
  SamplesPassed,                 // GL_SAMPLES_PASSED
  AnySamplesPassedConservative,  // GL_ANY_SAMPLES_PASSED_CONSERVATIVE
};

class BoxQuerySource final : public OcclusionQueries {
 public:
  explicit BoxQuerySource(std::uint32_t framebuffer,
                          QueryTarget target = QueryTarget::SamplesPassed,
                          GlStatePolicy state = GlStatePolicy::Restore);
  ~BoxQuerySource() override;
  BoxQuerySource(const BoxQuerySource&) = delete;
  BoxQuerySource& operator=(const BoxQuerySource&) = delete;

  const char* queryName() const override { return "gl-queries"; }
  Status beginQueryFrame(const Camera& camera) override;
  Status endQueryFrame() override;
  void noteDraw() override { pending_work_ = true; }
  void beginAccess() override { guard_.beginAccess(); }
  Status endAccess() override { return guard_.endAccess(); }

  QueryHandle issueBoxes(const QueryBox* boxes, std::size_t count) override;
  QueryHandle issueRects(const RectQuery* rects, std::size_t count) override;
  bool ready(QueryHandle handle) override;
  std::uint32_t result(QueryHandle handle) override;

  // Queries in flight (issued, not yet read).
  std::size_t inFlight() const { return pool_.size() - free_.size(); }

 private:
  static constexpr std::uint8_t kOpenQuery = 1;    // open_: issued, not read
  static constexpr std::uint8_t kFailedQuery = 2;  // open_: its issue failed: "visible"
  QueryHandle acquire();
  // A handle whose query failed with `error` (noted): it answers "visible".
  QueryHandle failedQuery(Status error);
  // Sets the pass's GL state in `scope` and binds `program` and the vertex array; false
  // if the scope failed.
  bool preparePass(GlStateGuard::Scope& scope, std::uint32_t program);
  void syncCounted();  // a poll or result call: counts a flush if work was pending

  std::uint32_t framebuffer_;
  std::uint32_t target_;
  Camera camera_;
  bool began_ = false;
  Status unusable_;  // its programs could not be made: every frame fails with this
  std::unique_ptr<Program> box_program_;
  std::unique_ptr<Program> rect_program_;
  std::int32_t u_boxes_ = -1, u_depth_ = -1;
  std::uint32_t vao_ = 0;
  std::uint32_t depth_func_ = 0;
  std::uint32_t clip_depth_mode_ = 0;
  std::vector<std::uint32_t> pool_;  // GL query objects
  std::vector<QueryHandle> free_;
  std::vector<std::uint8_t> open_;  // per handle: issued and not read
  std::vector<float> uniforms_;     // scratch: boxes packed for the uniform array
  GlStateGuard guard_;              // the application's GL state, saved and restored
  bool pending_work_ = false;
};

}  // namespace logrid::zread
