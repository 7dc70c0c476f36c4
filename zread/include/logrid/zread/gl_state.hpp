// GL-state independence for the GL depth sources: whatever state the application left
// on the context, a source's own draws and reads produce the fragments and pixels the
// source means, and the application finds its state as it left it.
//
// A source owns one GlStateGuard and opens a GlStateGuard::Scope around each piece of
// GL work (a submit, a collect, a resolve). The scope saves only what it is asked to set,
// sets it, and restores it exactly when it ends (also when an exception leaves the scope):
//
//   prepareDraw()   for the source's own draws (occlusion queries, resolves):
//                   face culling and winding, polygon mode, stencil test, depth test,
//                   function and write mask, depth clamp, depth range and viewport (index
//                   0), clip distances, sample mask, sample coverage, alpha to coverage
//                   and to one, multisampling, rasterizer discard, polygon offset (fill,
//                   line, point), scissor test and box (index 0), colour write masks (every
//                   draw buffer), the draw framebuffer, program, program pipeline and vertex
//                   array; and, where the driver has them, the depth bounds test
//                   (EXT_depth_bounds_test), the representative fragment test
//                   (NV_representative_fragment_test) and the exclusive scissor
//                   (NV_scissor_exclusive).
//   clipControl()   after prepareDraw(), for draws whose vertices come in a depth
//                   convention's clip space: the clip origin and depth mode.
//   prepareRead()   for glReadPixels and two-dimensional texture reads of depth, integer
//                   or normalised values: the read framebuffer, the pixel-pack buffer and
//                   the pack parameters such reads apply (alignment, row length, skip
//                   pixels and rows, swap bytes; image height and skipped images act on
//                   three-dimensional images, LSB-first on bitmaps and read colour
//                   clamping on float colour, none of which logrid reads).
//   prepareProgram() for compute dispatches: program, program pipeline.
//   bindTexture()   a texture on a texture unit for the source's shaders to fetch from:
//                   the active texture unit, the unit's binding for the target and its
//                   sampler object (replaced by a nearest, no-compare sampler), and the
//                   texture's swizzle, depth-stencil mode and base and maximum level.
//   bindStorageBuffer() a buffer range on an indexed shader-storage binding point: the
//                   point's buffer, offset and size, and the generic binding.
//
// Errors (logrid/error.hpp): a call that fails notes its Status (the first is kept, in
// the FirstError the guard was given — a source's own, so that DepthSource::takeError()
// and endAccess() report it — or the guard's: takeError()), marks the scope failed
// (Scope::ok() false; its prepare and bind calls return false and its later calls do
// nothing) and leaves the source to answer without GL ("visible"). What cannot be saved
// is refused that way, with a message that says what to change, before anything is set:
//   * conditional rendering (there is no glGet for it; it is detected with a probe:
//     glBeginConditionalRender fails with GL_INVALID_OPERATION only while it is active);
//   * transform feedback that is active and not paused (a program cannot be changed then);
//   * a GL error pending from the application's own calls (it would be taken for the
//     source's, and glGetError cannot put it back): the scope fails as it opens.
// After its GL calls a source calls check(), which fails naming the call if GL reported
// an error.
//
// Access windows: the guard above works per scope, so a source that reads one tile at a
// time queries and restores the state once per tile. Between beginAccess() and
// endAccess() every scope of the guard shares one window instead: the state is saved at
// the window's first prepare call, set again (without queries) by later ones, restored
// by endAccess(), and the GL errors of the window's calls are checked once, in
// endAccess(), which reports them as check() does. Only logrid's own GL calls may run in a
// window: the culler opens one on each source for the span of one Culler::nextBatch()
// (DepthSource::beginAccess), the application's draws come between windows. A window
// costs about 15 queries however many reads it holds. A scope of another guard that opens
// while a window is open closes that window first (it restores its state), so that
// two sources' saves and restores nest.
//
// Who keeps the application's state is the guard's GlStatePolicy:
//   Restore             the default: everything above.
//   ApplicationManaged  for an application that tracks its own GL state (a state cache
//                       that it invalidates, or sets everything it draws with before
//                       drawing): the guard queries nothing, sets what the prepare and
//                       bind calls list above, and leaves it so; it refuses nothing, and
//                       checks GL errors once per window (or scope outside one). The
//                       application's part of the contract: after a source ran (after
//                       each Culler::nextBatch() or cullFrame()), the state the source's
//                       passes set (gl_sources.hpp lists them per source) holds logrid's
//                       values until the application sets its own; it leaves no GL error
//                       pending, no conditional rendering active and no transform feedback
//                       active and unpaused when logrid runs. What logrid's passes need is
//                       set by them under either policy: the application never sets
//                       state for logrid.
//
// One thing is restored as GL allows and not exactly: a program the application deleted
// while it was current ceases to exist once the source switches away from it, so the
// program binding is restored to 0 in that case (as if the application had unbound it).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "logrid/error.hpp"
#include "logrid/types.hpp"

namespace logrid::zread {

// Who keeps the application's GL state (above).
enum class GlStatePolicy : std::uint8_t {
  Restore,             // logrid saves and restores what it changes (the default)
  ApplicationManaged,  // logrid queries nothing and leaves what it set
};

class GlStateGuard {
 public:
  // Upper bounds of the per-index state saved (drivers report 8, 8 and 1).
  static constexpr int kMaxClipDistances = 32;
  static constexpr int kMaxDrawBuffers = 32;
  static constexpr int kMaxSampleMaskWords = 4;
  static constexpr int kMaxTextures = 2;
  static constexpr int kMaxStorageBuffers = 2;

  // Needs a current GL 4.5 context; creates the query object of the conditional-rendering
  // probe. Not copyable: the query belongs to this context. `query_counter` (optional)
  // is where stateQueries() counts, e.g. a source's ReadCounters::state_queries;
  // `errors` (optional) where its errors are noted, e.g. a source's (DepthSource::fail).
  // A driver beyond the limits below makes every scope fail (Unsupported).
  explicit GlStateGuard(GlStatePolicy policy = GlStatePolicy::Restore,
                        std::uint64_t* query_counter = nullptr, FirstError* errors = nullptr);
  ~GlStateGuard();
  GlStateGuard(const GlStateGuard&) = delete;
  GlStateGuard& operator=(const GlStateGuard&) = delete;

  class Scope;

  // Opens an access window (above); nothing is queried or set until a scope's prepare
  // call. Does nothing if one is open.
  void beginAccess();
  // Closes the window: restores what its scopes saved, notes an error naming the first
  // call of the window if GL reported one (the state is restored then too), and returns
  // takeError(). Only takes the error if no window is open.
  Status endAccess();
  bool inAccess() const { return access_; }
  // The first error noted since the last takeError(), and clears it (ok if none).
  Status takeError() { return errors_->take(); }

  GlStatePolicy policy() const { return policy_; }
  // GL state queries made so far (glGet*, glIsEnabled*, glIs*, glGetError, the
  // conditional-rendering probe): what the guard costs a threaded driver, where each
  // query waits for the driver's thread.
  std::uint64_t stateQueries() const { return *queries_; }

 private:
  friend class Scope;
  // Ends the window's outer scope (restoring), checking errors first if `check`.
  void closeWindow(bool check);
  // Closes the window another guard has open on this thread (its errors stay noted).
  static void closeOtherWindow(GlStateGuard& guard);

  GlStatePolicy policy_;
  std::uint64_t own_queries_ = 0;
  std::uint64_t* queries_;
  FirstError own_errors_;
  FirstError* errors_;
  Status unusable_;  // the driver's limits are beyond what the guard saves
  bool access_ = false;
  std::unique_ptr<Scope> window_;  // the open window's outer scope, from its first scope
  std::string unchecked_;          // the window's first call whose errors are unchecked
  std::uint32_t probe_query_ = 0;
  std::uint32_t sampler_ = 0;
  std::int32_t clip_distances_ = 0;
  std::int32_t draw_buffers_ = 0;
  std::int32_t sample_mask_words_ = 0;
  bool depth_bounds_ = false;
  bool representative_fragment_ = false;
  bool scissor_exclusive_ = false;
};

class GlStateGuard::Scope {
 public:
  // `who` names the source and call in every message (e.g. "QuerySource::submit").
  // Fails if a GL error is pending (nothing is changed then). In an access window the
  // scope is a view of the window's: it saves into it, and neither checks nor restores
  // on its own.
  Scope(GlStateGuard& guard, const char* who);
  // Restores everything the prepare and bind calls saved, in reverse order.
  ~Scope();
  Scope(const Scope&) = delete;
  Scope& operator=(const Scope&) = delete;

  // No call of the scope (or of its window) failed. The calls below that return a bool
  // return ok() after them; those that do not do nothing once it is false.
  bool ok() const;
  // Notes an error of the caller's own work in the scope (a buffer it could not map, an
  // attachment it cannot read): the scope fails as if a call of its own had.
  void fail(Status error);

  // Sets the neutral raster state listed above for draws into `framebuffer`, with the
  // viewport and the scissor box at [0, width) x [0, height), the scissor test on, depth
  // range [0, 1], the depth test on with `depth_func` and `depth_write`, colour writes
  // off unless `color_write`, and no program or vertex array change (bind your own
  // afterwards: they are saved here). Fails, before setting anything, if conditional
  // rendering or unpaused transform feedback is active.
  [[nodiscard]] bool prepareDraw(std::uint32_t framebuffer, std::int32_t width, std::int32_t height,
                                 std::uint32_t depth_func, bool depth_write,
                                 bool color_write = false);
  // Moves the scissor box (index 0) after prepareDraw().
  void scissor(const PixelRect& rect);
  // Sets glClipControl(origin, depth_mode) (e.g. GL_LOWER_LEFT, GL_ZERO_TO_ONE), saving
  // the application's clip origin and depth mode first.
  void clipControl(std::uint32_t origin, std::uint32_t depth_mode);
  // Sets the read framebuffer, the pixel-pack buffer (0: client memory), and tightly
  // packed rows with alignment 1, no skips and no byte swapping.
  [[nodiscard]] bool prepareRead(std::uint32_t framebuffer, std::uint32_t pack_buffer);
  // Saves program and program pipeline for a compute dispatch; fails like prepareDraw()
  // if conditional rendering or unpaused transform feedback is active.
  [[nodiscard]] bool prepareProgram();
  // Binds `texture` (of `target`, e.g. GL_TEXTURE_2D_MULTISAMPLE) to texture unit `unit`
  // with a nearest, no-compare sampler, identity swizzle, base level 0 (texelFetch's
  // level is then the texture's level) and, for depth-stencil formats, depth (not
  // stencil) sampling. At most kMaxTextures textures per scope, on different
  // units; binding the same texture to the same unit again does nothing.
  [[nodiscard]] bool bindTexture(std::uint32_t unit, std::uint32_t target, std::uint32_t texture);

  // Binds [offset, offset + size) of `buffer` to shader-storage binding point `index`
  // (size 0: the whole buffer). At most kMaxStorageBuffers per scope.
  [[nodiscard]] bool bindStorageBuffer(std::uint32_t index, std::uint32_t buffer,
                                       std::int64_t offset, std::int64_t size);

  // Fails naming `call` if GL reported an error since the last check; returns ok(). In
  // an access window the check waits for GlStateGuard::endAccess().
  [[nodiscard]] bool check(const char* call);

  // Is conditional rendering active? (The probe, or its own error; exposed for tests.)
  static Result<bool> conditionalRenderingActive(std::uint32_t probe_query);

 private:
  struct Window {};
  Scope(GlStateGuard& guard, const char* who, Window);
  void open();
  bool saving() const { return guard_.policy_ == GlStatePolicy::Restore; }
  bool refuseUnsavable();
  void restore();
  std::uint8_t enabled(std::uint32_t cap);
  std::int32_t integer(std::uint32_t name);

  GlStateGuard& guard_;
  const char* who_;
  Scope* window_ = nullptr;  // the access window's outer scope this one is a view of
  bool failed_ = false;
  bool draw_saved_ = false;
  bool clip_saved_ = false;
  bool read_saved_ = false;
  bool program_saved_ = false;
  int textures_saved_ = 0;
  int storage_saved_ = 0;

  struct DrawState {
    std::uint8_t cull_face = 0, depth_test = 0, stencil_test = 0, depth_clamp = 0,
                 rasterizer_discard = 0, offset_fill = 0, offset_line = 0, offset_point = 0,
                 scissor_test = 0, sample_mask = 0, sample_coverage = 0, alpha_to_coverage = 0,
                 alpha_to_one = 0, multisample = 0, depth_bounds = 0, representative = 0,
                 scissor_exclusive = 0, depth_mask = 0, coverage_invert = 0;
    std::int32_t cull_mode = 0, front_face = 0, polygon_mode = 0, depth_func = 0;
    double depth_range[2] = {0, 1};
    double depth_bounds_range[2] = {0, 1};
    float viewport[4] = {};
    std::int32_t scissor_box[4] = {};
    float coverage_value = 1, offset_factor = 0, offset_units = 0;
    std::int32_t draw_framebuffer = 0;
    std::uint8_t clip_distances[kMaxClipDistances] = {};
    std::uint8_t color_masks[4 * kMaxDrawBuffers] = {};  // RGBA per draw buffer
    std::int32_t sample_mask_words[kMaxSampleMaskWords] = {};
  } draw_;
  std::int32_t clip_origin_ = 0, clip_depth_mode_ = 0;
  struct ProgramState {
    std::int32_t program = 0, pipeline = 0, vertex_array = 0;
  } program_;
  struct ReadState {
    std::int32_t read_framebuffer = 0, pack_buffer = 0, alignment = 4, row_length = 0,
                 skip_pixels = 0, skip_rows = 0, swap_bytes = 0;
  } read_;
  struct TextureState {
    std::uint32_t unit = 0, target = 0, texture = 0;
    std::int32_t active = 0, bound = 0, sampler = 0;
    std::int32_t swizzle[4] = {};
    std::int32_t depth_stencil_mode = 0;
    std::int32_t base_level = 0, max_level = 1000;
    bool has_depth_stencil_mode = false;
    bool has_levels = false;
  } textures_[kMaxTextures];
  struct StorageState {
    std::uint32_t index = 0;
    std::int32_t generic = 0, buffer = 0;
    std::int64_t start = 0, size = 0;
  } storage_[kMaxStorageBuffers];
};

}  // namespace logrid::zread
