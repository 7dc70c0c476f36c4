// A conservative CPU occlusion buffer: a depth source that needs no read from the
// renderer at all. The application's draw callback tells it which object it drew
// (drawObject), it rasterises that object's triangles (or a simpler occluder model,
// occluder_mesh.hpp) into a depth buffer in memory, and the grid reads that buffer
// instead of the GPU's. Everything is lazy, as the grid is: drawObject() only notes the
// object; a request sets up the triangles of the objects that may cover its rectangle,
// bins them by tile, and rasterises only the tiles it touches.
//
// What the buffer holds: per pixel a depth key (types.hpp) that is never nearer than
// the key GL stores there after drawing the same objects, and the clear key wherever GL
// might not have drawn. The grid's answers from it are therefore answers about a depth
// buffer that is everywhere at or behind GL's, and every box it finds occluded is
// occluded in GL's buffer too. Where GL might not cover a pixel, the buffer stays clear.
//
// Coverage (which pixel centres GL surely covers)
// ------------------------------------------------
// A GL rasteriser snaps each window-space vertex to a sub-pixel grid (at least 4 bits,
// so a vertex moves by up to s = 2^-4 pixel per axis if it truncates; ProjectionSettings::
// subpixel_bits), after a float vertex transform whose error the buffer bounds as
// projection.hpp does (kRenderErrorUlps, per object box, per axis), and covers a pixel
// centre by the top-left rule. The buffer computes the triangles exactly (double) and
// claims a centre q for triangle T only when, for the set D of T and the neighbours of
// T across the edges q lies within s of:
//   * every triangle of D has a nonzero area and is counted with the orientation that
//     makes it counter-clockwise on screen; two triangles are neighbours when they share
//     an edge between the same two welded vertices and lie on opposite sides of it on
//     screen (so the edge cancels in the boundary of D);
//   * q lies on the inner side of every edge of D's boundary (and of the near-plane clip
//     line of a triangle that crosses the near plane) by more than s, measured in the
//     max-norm: E(q) > s_x |a| + s_y |b| for an edge E = a x + b y + c.
// Then the winding number of D's boundary around q is at least 1 (q is to the left of
// every boundary edge), and it stays so while every vertex moves by at most s, because q
// never meets a moved boundary edge. So GL, after snapping, covers q with a triangle of
// D in its original orientation: GL draws it (logrid's renderer draws both faces). This
// closes the cracks a per-triangle rule would leave along every shared edge, and stays
// clear on silhouettes and folds, where GL might indeed leave a centre uncovered.
//
// Depth (never nearer than GL)
// ----------------------------
// GL stores at q at most the depth of any fragment it wrote there (the depth test keeps
// the nearer), hence at most the depth of the triangle T'' of D that covers q. A GPU
// interpolates T''s depth from its snapped vertices, i.e. T''s exact depth plane at a
// point within s of q; Mesa's llvmpipe evaluates the plane of the unsnapped float
// vertices at q itself (docs/ANALYSIS.md). Both are at most
//   plane_T''(q) + |dz/dx| s_x + |dz/dy| s_y.
// For T'' = T that is the stored key's plane plus that slack. For a neighbour B across
// an edge q lies within s of, the two planes agree on the edge, so plane_B(q) exceeds
// plane_T(q) by at most (g_T + g_B) s (g = |dz/dx| + |dz/dy|); the buffer adds it, and
// B's own slack, only to such centres. On top: the object box's depth margin
// (projection.hpp: quantisation step, render error of GL's vertex depths), and the
// float error of the buffer's own plane evaluation. Keys at or beyond the clear key
// leave the pixel clear; triangles with a vertex beyond the far plane are left out.
//
// Resolution
// ----------
// Full: one buffer pixel per viewport pixel. Half and quarter: one per 2x2 or 4x4 block.
// A block is covered only if every pixel centre in it is, and holds the farthest key of
// them: the rules above are applied to the square spanned by the block's centres (its
// half-width r = 0.5 or 1.5 pixel is added to every slack and to the depth terms). A
// request about viewport pixels is answered as if each held its block's key. A
// multisampled renderer (Camera::multisample) may cover a sample of a pixel and miss
// another, and the depth sources keep a pixel's farthest sample: its pixels count as
// squares of half-width 0.5 (every sample lies within half a pixel of the centre), so r
// grows by 0.5 at every resolution.
//
// Masked (OcclusionBufferDesc::representation), after masked occlusion culling: per block
// of 8 x 4 buffer pixels a coverage mask M and two keys, z_layer and z_far; a pixel's key
// is z_layer if its bit in M is set, z_far otherwise. A triangle reaching a block is
// classified and tested sample by sample exactly as in the per-pixel buffer (the same
// coverage rules, the same key bounds), and lands as the mask C of the samples it claims
// and the largest key bound k of them. The block keeps, for every pixel p, the invariant
//   key(p) >= min(key_before(p), k if p is in C),
// which is all the per-pixel buffer's min() guarantees, so the argument above carries
// over unchanged: every key is at or behind a key the per-pixel buffer may hold there,
// never nearer than GL's. Merging (raster_kernel.inl, mergeMasked), with k_n = min(
// z_layer, k) and k_f = max(z_layer, k):
//   * k >= z_far: the triangle is dropped (no pixel gains);
//   * M and C cover the block together: z_far = k_f, and the layer keeps the pixels
//     whose bound is k_n (those of M, or those of C) with z_layer = k_n;
//   * else the triangle joins the layer: M |= C and z_layer = the largest of z_layer
//     over M \ C, k over C \ M and k_n over C and M.
// When M covers the block, z_far = z_layer and M = 0. (The paper would rather start a
// new layer from a triangle nearer z_far than z_layer, the old layer's pixels falling
// back to z_far; on the forest that left more pixels clear and drew more objects, and so
// did dropping such triangles.) The coarser representation holds farther keys than the
// per-pixel one (a block's layer holds the farthest claimed sample of what joined it),
// so it culls less; a request is answered from the keys it implies.
// OcclusionBufferDesc::unsafe_masked_merge breaks the join rule.
//
// Models inside the object (OccluderObject::inside_solid): a triangle inside a closed
// convex solid S that GL draws is hidden by S wherever its claims hold: the claimed
// centre lies inside the model's projection by more than s, hence inside S's by more
// than s, so S's front faces cover it; and every front face's plane is a supporting
// plane of the convex S, so GL's depth there is at most S's, which is at most the
// model's. Valid only while the eye is outside S and S is not clipped: the buffer uses
// the model only when the object box lies wholly beyond the near plane (it contains the
// eye otherwise), and the fallback (or nothing) else.
//
// Moving objects (drawObject with an ObjectTransform): the application draws the
// object's vertices p (the occluder meshes' coordinates, the object's own) at R p + t,
// as MeshRenderer does (gl/mesh_renderer.hpp): R and t - render_origin rounded to float
// once, R p + (t - render_origin) computed in float. The buffer places each vertex at
// R p + t in double (off by 2^-53 relative, far below what follows) and bounds how far
// GL's vertex may lie from it, per axis:
//   * the rotation's rounding: R's elements (1 u each), three products and two sums
//     (gamma_3 = 3 u): 4 u of sum_j |R_ij| |p_j| <= max|R| |p|_1;
//   * the offset's rounding: u |t - render_origin| <= u |R p + t - render_origin| +
//     u |R p|: the first part is the rounding of the same sum for a still object (the
//     render error, projection.hpp, covers it: 17 u of its 32 are used), the second at
//     most 1 u of max|R| |p|_1.
// So GL's vertex lies within pad = 16 u max(1, max|R|) |p|_1 (|p|_1 bounded over the
// object's box, the mover's box pad of samples/scene/motion.hpp; 5 u needed, the rest
// spare) of the placed vertex on each axis, beyond the render error modelled at the
// placed vertex. The set-up adds the pad to every vertex as the render error is added:
// a world displacement d (|d_j| <= pad) moves clip coordinate r by at most
// D_r = pad sum_j |M_rj| (M the view-projection), hence window x by at most
// (D_x + |ndc_x| D_w) / (w - D_w) times half the viewport, and the key likewise (a
// triangle with a corner where w <= D_w is left out): the coverage slack and the depth
// margin grow by as much, and every rule above holds for the placed, padded vertices.
// Welded vertices stay bit-identical after the placement in the buffer and in GL (the
// same float inputs through the same transform), so shared edges stay shared. A
// transform with a negative determinant turns the winding of a closed surface round;
// the back-face rule follows it, and a singular one (determinant 0) rasterises every
// triangle.
//
// Threads: with OcclusionBufferDesc::threads = N > 0, the buffer runs binned rasterisation
// on N threads: the caller and a pool of N - 1 started threads that knows nothing of the
// buffer (cpu/src/worker_pool.hpp). drawObject() numbers the object in draw order and
// posts it to the pool; a thread sets it up into its own triangle store and bins each
// triangle into the tiles (bins) its bounds touch, in its own per-bin lists, while the
// application goes on drawing. A request first finishes the set-ups (the caller takes
// those not yet started), then has the threads rasterise the requested bins that have
// triangles waiting, each bin taken whole by one thread: no two threads ever write one
// tile, and there are no per-tile locks. A bin's triangles are merged from the threads'
// lists in draw order (object, then triangle), so every bin sees the same triangles in
// the same order for any N: the keys are bit-identical for every thread count, masked
// blocks (which depend on the order) included, and per pixel they equal the lazy
// caller's (a key is the minimum of its bounds, whatever the order). Every drawn object
// is set up; only requested tiles are rasterised. The time the caller spends in requests
// finishing set-ups and rasterising is counted as wait_seconds. Without threads
// (N = 0), everything runs lazily inside the requests: objects are set up only when a
// request touches their rectangle, and only the requested tiles are rasterised.
//
// One frame: beginFrame(camera) after the application cleared its depth buffer;
// drawObject(id) for every object drawn (Culler: from the draw callback); requests
// through the DepthSource interface; endFrame(). Not thread-safe: one caller at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "logrid/camera.hpp"
#include "logrid/cpu/occluder_mesh.hpp"
#include "logrid/depth_source.hpp"
#include "logrid/error.hpp"
#include "logrid/projection.hpp"

namespace logrid::cpu {

enum class Resolution : std::uint8_t { Full = 1, Half = 2, Quarter = 4 };

// What the buffer holds per pixel (see "Masked" above): a key each, or per block of 8 x 4
// buffer pixels a coverage mask and two keys.
enum class Representation : std::uint8_t { PerPixel, Masked };

// The SIMD kernel. Auto picks the widest the CPU runs (AVX2, then SSE4.1, then scalar);
// every kernel writes bit-identical buffers (same operations in the same order).
enum class Isa : std::uint8_t { Auto, Scalar, Sse41, Avx2 };

const char* toString(Resolution);
const char* toString(Isa);
const char* toString(Representation);
// Parse "full" / "half" / "quarter", "auto" / "scalar" / "sse4.1" / "avx2" and
// "per-pixel" / "masked".
bool parseResolution(const std::string& text, Resolution& out);
bool parseIsa(const std::string& text, Isa& out);
bool parseRepresentation(const std::string& text, Representation& out);
// Whether this CPU runs a kernel (Auto and Scalar always).
bool isaSupported(Isa isa);

struct OcclusionBufferDesc {
  Resolution resolution = Resolution::Full;
  Representation representation = Representation::PerPixel;
  Isa isa = Isa::Auto;
  // Threads that set up and rasterise, the caller among them (0: everything in the
  // caller, lazily; 1: binned, in the caller alone; see "Threads").
  std::uint32_t threads = 0;
  // The same settings the culler projects boxes with: sub-pixel bits (coverage slack),
  // render error and quantisation (depth margins). The defaults are the safe ones.
  ProjectionSettings projection;
  // Closed surfaces (OccluderMeshes::closed()) are rasterised with only the triangles
  // that face the eye (counter-clockwise on screen): the others cover nothing more and
  // lie behind them. Set to rasterise every triangle.
  bool closed_back_faces = false;
  // Occluder selection: what each drawn object is expected to hide. An object is
  // rasterised only if its box covers at least `min_pixels_per_triangle` viewport
  // pixels for each triangle of its occluder (screen size against cost: near, large and
  // solid objects, whose models have few triangles, pass first), and only while the
  // frame's selected occluder triangles stay within `triangle_budget` (0: no budget),
  // taken in the order drawn (the culler draws roughly front to back). Leaving an
  // occluder out only leaves keys farther: always conservative.
  double min_pixels_per_triangle = 0;
  std::uint32_t triangle_budget = 0;
  // Test aids that break the conservative rules on purpose (tests show what each rule
  // prevents): no coverage slack at all (exact edges, as if GL did not snap), and no
  // depth slack (the exact plane, no margin, no snapping term).
  bool unsafe_exact_coverage = false;
  bool unsafe_exact_depth = false;
  // Test aid of the masked representation: a triangle joining a block's non-empty layer
  // sets the layer's key to the nearer of the two instead of the farthest bound of the
  // union (pixels only one of them claims get a key nearer than their bound).
  bool unsafe_masked_merge = false;
};

// Where the application draws a moving object ("Moving objects" above): its vertices p
// at rotation * p + translation (rotation 3x3, column-major), in the coordinates the
// Camera's view_projection takes. Finite; the identity is a still object.
struct ObjectTransform {
  double rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  DVec3 translation;
};

// Returns an empty string if the descriptor is usable, else a message naming the field.
std::string validateOcclusionBufferDesc(const OcclusionBufferDesc& desc);

// What the buffer did, accumulated since construction (take differences per frame).
struct OcclusionBufferStats {
  std::uint64_t objects_drawn = 0;         // drawObject() calls
  std::uint64_t objects_set_up = 0;        // objects whose triangles were set up
  std::uint64_t objects_fallback = 0;      // models replaced by their fallback
  std::uint64_t objects_skipped = 0;       // models without a usable fallback, empty objects
  std::uint64_t objects_unselected = 0;    // left out by the occluder selection
  std::uint64_t objects_moved = 0;         // drawObject() calls with a transform
  std::uint64_t triangles_selected = 0;    // triangles of the selected occluders
  std::uint64_t triangles_set_up = 0;      // triangles transformed and set up
  std::uint64_t triangles_rasterized = 0;  // triangle-tile pairs rasterised
  std::uint64_t tiles_rasterized = 0;      // tiles brought up to date
  double seconds = 0;         // CPU time of the caller inside the buffer (drawObject, requests)
  double wait_seconds = 0;    // of which finishing the set-ups and rasterising (threads > 0)
  double worker_seconds = 0;  // time the started threads spent on set-up and raster tasks
};

class OcclusionBuffer final : public DepthSource, public KeyReader {
 public:
  // `meshes` must outlive the buffer. An error (InvalidArgument) for an invalid
  // descriptor or an ISA this CPU does not run; both forms (logrid/error.hpp).
  static Result<std::unique_ptr<OcclusionBuffer>> create(const OccluderMeshes& meshes,
                                                         const OcclusionBufferDesc& desc = {});
  explicit OcclusionBuffer(const OccluderMeshes& meshes, const OcclusionBufferDesc& desc = {});
  ~OcclusionBuffer() override;
  OcclusionBuffer(const OcclusionBuffer&) = delete;
  OcclusionBuffer& operator=(const OcclusionBuffer&) = delete;

  const OcclusionBufferDesc& desc() const { return desc_; }
  Isa isa() const;  // the kernel in use (never Auto)

  DepthSourceTraits traits() const override {
    return {"cpu", true, false};
  }  // reads depth, synchronous
  // An error for an invalid camera (validateCamera) or projection settings.
  Status beginFrame(const Camera& camera) override;
  Status endFrame() override;

  // The application drew object `id` of the meshes this frame (its depth is in GL's
  // buffer). An error (InvalidArgument) for an id outside the meshes or outside a frame.
  Status tryDrawObject(std::uint32_t id);
  void drawObject(std::uint32_t id);
  // The same for an object the application drew moved by `transform` (see "Moving
  // objects"); also an error (InvalidArgument) for a transform that is not finite.
  Status tryDrawObject(std::uint32_t id, const ObjectTransform& transform);
  void drawObject(std::uint32_t id, const ObjectTransform& transform);

  // Synchronous: every answer is written inside submit(). Summary and Count requests
  // describe the buffer's keys (never nearer than GL's, see above).
  void submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) override;
  void readKeys(const PixelRect& rect, float* keys) override;

  const OcclusionBufferStats& stats() const;

 private:
  struct Checked {};                                               // the descriptor was validated
  static Checked checkedOrThrow(const OcclusionBufferDesc& desc);  // the throwing form's check
  OcclusionBuffer(Checked, const OccluderMeshes& meshes, const OcclusionBufferDesc& desc);
  Status drawChecked(std::uint32_t id, const ObjectTransform* transform);

  struct Impl;
  std::unique_ptr<Impl> impl_;
  OcclusionBufferDesc desc_;
};

#if LOGRID_HAS_EXCEPTIONS
inline OcclusionBuffer::Checked OcclusionBuffer::checkedOrThrow(const OcclusionBufferDesc& desc) {
  std::string problem = validateOcclusionBufferDesc(desc);
  if (!problem.empty()) throw Error(ErrorCode::InvalidArgument, std::move(problem));
  return {};
}
inline OcclusionBuffer::OcclusionBuffer(const OccluderMeshes& meshes,
                                        const OcclusionBufferDesc& desc)
    : OcclusionBuffer(checkedOrThrow(desc), meshes, desc) {}
inline void OcclusionBuffer::drawObject(std::uint32_t id) { orThrow(tryDrawObject(id)); }
inline void OcclusionBuffer::drawObject(std::uint32_t id, const ObjectTransform& transform) {
  orThrow(tryDrawObject(id, transform));
}
#endif

}  // namespace logrid::cpu
