#include "logrid/cpu/occlusion_buffer.hpp"

#include <algorithm>
#include <bitset>
#include <chrono>
#include <cmath>
#include <deque>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>

#include "logrid/elapsed.hpp"
#include "logrid/error.hpp"
#include "raster/raster_triangle.hpp"
#include "triangle_setup.hpp"
#include "worker_pool.hpp"

namespace logrid::cpu {

const char* toString(Resolution r) {
  switch (r) {
    case Resolution::Full: return "full";
    case Resolution::Half: return "half";
    case Resolution::Quarter: return "quarter";
  }
  return "?";
}

const char* toString(Isa isa) {
  switch (isa) {
    case Isa::Auto: return "auto";
    case Isa::Scalar: return "scalar";
    case Isa::Sse41: return "sse4.1";
    case Isa::Avx2: return "avx2";
  }
  return "?";
}

const char* toString(Representation r) {
  switch (r) {
    case Representation::PerPixel: return "per-pixel";
    case Representation::Masked: return "masked";
  }
  return "?";
}

bool parseRepresentation(const std::string& text, Representation& out) {
  for (Representation r : {Representation::PerPixel, Representation::Masked}) {
    if (text == toString(r)) {
      out = r;
      return true;
    }
  }
  return false;
}

bool parseResolution(const std::string& text, Resolution& out) {
  for (Resolution r : {Resolution::Full, Resolution::Half, Resolution::Quarter}) {
    if (text == toString(r)) {
      out = r;
      return true;
    }
  }
  return false;
}

bool parseIsa(const std::string& text, Isa& out) {
  for (Isa i : {Isa::Auto, Isa::Scalar, Isa::Sse41, Isa::Avx2}) {
    if (text == toString(i)) {
      out = i;
      return true;
    }
  }
  return false;
}

bool isaSupported(Isa isa) { return isa == Isa::Auto || detail::kernels(isa).raster != nullptr; }

std::string validateOcclusionBufferDesc(const OcclusionBufferDesc& d) {
  std::ostringstream out;
  if (d.resolution != Resolution::Full && d.resolution != Resolution::Half &&
      d.resolution != Resolution::Quarter) {
    out << "OcclusionBuffer: resolution " << int(d.resolution)
        << " is unknown; use full, half or quarter";
  } else if (d.representation != Representation::PerPixel &&
             d.representation != Representation::Masked) {
    out << "OcclusionBuffer: representation " << int(d.representation)
        << " is unknown; use per-pixel or masked";
  } else if (d.isa != Isa::Auto && d.isa != Isa::Scalar && d.isa != Isa::Sse41 &&
             d.isa != Isa::Avx2) {
    out << "OcclusionBuffer: ISA " << int(d.isa) << " is unknown; use auto, scalar, sse4.1 or avx2";
  } else if (!isaSupported(d.isa)) {
    out << "OcclusionBuffer: this CPU does not run the " << toString(d.isa)
        << " kernel; use auto (picks the widest it runs) or scalar";
  } else if (!(d.min_pixels_per_triangle >= 0) || !std::isfinite(d.min_pixels_per_triangle)) {
    out << "OcclusionBuffer: min_pixels_per_triangle " << d.min_pixels_per_triangle
        << " must be a finite number >= 0 (0: every object is an occluder)";
  } else if (d.threads > 64) {
    out << "OcclusionBuffer: " << d.threads << " worker threads is too many; use 0 to 64";
  } else {
    const std::string p = validateProjectionSettings(d.projection);
    if (!p.empty()) out << "OcclusionBuffer: " << p;
  }
  return out.str();
}

namespace {

using Clock = std::chrono::steady_clock;

// Bins are tiles of the buffer, kBinViewport viewport pixels on a side at full resolution
// (a grid tile of the default size), never narrower than one 8-wide store.
constexpr std::int32_t kBinViewport = 32;

constexpr double kU = 1.0 / 16777216.0;  // float unit roundoff, 2^-24

// How far GL may put a vertex of an object inside `box` (its own coordinates) from where
// `t` places it, per axis (the header, "Moving objects"): 16 u max(1, max|R|) |p|_1.
double placementPad(const Aabb& box, const ObjectTransform& t) {
  const double size = std::max(std::fabs(box.min.x), std::fabs(box.max.x)) +
                      std::max(std::fabs(box.min.y), std::fabs(box.max.y)) +
                      std::max(std::fabs(box.min.z), std::fabs(box.max.z));
  double r_max = 1;
  for (double e : t.rotation) r_max = std::max(r_max, std::fabs(e));
  return 16 * kU * r_max * size;
}

// The box of every vertex of `box` as GL draws it placed by `t`: the bounds of the eight
// placed corners (each vertex is a convex combination of them, and so is its placement),
// widened by the pad and rounded outwards to float.
Aabb placedBox(const Aabb& box, const ObjectTransform& t, double pad) {
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  const double tr[3] = {t.translation.x, t.translation.y, t.translation.z};
  for (int c = 0; c < 8; ++c) {
    const double q[3] = {(c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                         (c & 4) ? box.max.z : box.min.z};
    for (int r = 0; r < 3; ++r) {
      const double v =
          t.rotation[r] * q[0] + t.rotation[3 + r] * q[1] + t.rotation[6 + r] * q[2] + tr[r];
      lo[r] = std::min(lo[r], v);
      hi[r] = std::max(hi[r], v);
    }
  }
  // The double sums above are off by far less than the pad's 2^-20 relative; widen by
  // the pad and one float step outwards.
  auto down = [](double v) { return std::nextafter(float(v), -HUGE_VALF); };
  auto up = [](double v) { return std::nextafter(float(v), HUGE_VALF); };
  Aabb out;
  out.min = {down(lo[0] - pad), down(lo[1] - pad), down(lo[2] - pad)};
  out.max = {up(hi[0] + pad), up(hi[1] + pad), up(hi[2] + pad)};
  return out;
}

// The sign of the determinant of a 3x3 column-major matrix (0: singular).
int orientation(const double* m) {
  const double det = m[0] * (m[4] * m[8] - m[7] * m[5]) - m[3] * (m[1] * m[8] - m[7] * m[2]) +
                     m[6] * (m[1] * m[5] - m[4] * m[2]);
  return det > 0 ? 1 : det < 0 ? -1 : 0;
}

}  // namespace

struct OcclusionBuffer::Impl {
  struct Bin {
    std::uint32_t stamp = 0;       // frame whose clear this bin has had
    std::vector<float> block_max;  // per 8 x 8 block: an upper bound of its keys
    std::vector<std::uint32_t> pending;
  };
  struct PendingObject {
    detail::SetupObject object;
    PixelRect rect;  // viewport pixels the object may cover
  };

  // Binned rasterisation on workers (desc.threads > 0; the header, "Threads"). A
  // triangle set up by a worker, in that worker's store: `seq` is its object's place in
  // the frame's draw order, `tri` its index in the store.
  struct Entry {
    std::uint32_t seq, tri;
  };
  // What one worker thread of the pool owns: written only by the task running on it
  // (set-up or raster), read by others only across the pool's wait().
  struct Worker {
    detail::TriangleSetup setup;
    std::vector<detail::RasterTriangle> tris;  // [0, tri_count): set up by this worker this frame
    std::size_t tri_count = 0;
    // Per bin, the triangles this worker set up that are not yet rasterised, in the order
    // set up (the worker takes objects in draw order, so ascending seq).
    std::vector<std::vector<Entry>> bin_entries;
    std::vector<std::uint32_t> list;  // raster scratch: one run of triangles for the kernel
    std::vector<std::size_t> cursor;  // raster scratch: per worker, entries of a bin merged
    OcclusionBufferStats counted;     // added to `stats` by the caller after the pool's wait()
  };
  // An object handed to the set-up workers (kept in a deque: its address stays valid
  // while the caller hands over more).
  struct Handed {
    Impl* impl;
    PendingObject object;
    std::uint32_t seq;
  };

  Impl(const OccluderMeshes& m, const OcclusionBufferDesc& d) : meshes(m), desc(d) {
    isa = d.isa == Isa::Auto ? detail::bestIsa() : d.isa;
    kernels = detail::kernels(isa);
    // N threads: the caller (worker N - 1 of the pool's tasks) and N - 1 started.
    workers.resize(d.threads);
    // The set-up in groups of four goes with the AVX2 kernels (both bit for bit as scalar).
    setup.useGroups(isa == Isa::Avx2);
    for (Worker& w : workers) w.setup.useGroups(isa == Isa::Avx2);
    if (d.threads > 0) pool = std::make_unique<detail::WorkerPool>(d.threads - 1);
  }
  ~Impl() { pool.reset(); }  // finishes the tasks queued (they use the workers' stores)

  const OccluderMeshes& meshes;
  OcclusionBufferDesc desc;
  Isa isa;
  detail::Kernels kernels;
  OcclusionBufferStats stats;

  bool in_frame = false;
  std::optional<Projector> projector;
  detail::SetupFrame frame;
  double snap_half = 0;  // the other half of a sub-pixel step (projection.hpp widens by half)
  std::int32_t scale = 1;
  std::int32_t width = 0, height = 0;  // viewport
  std::int32_t bw = 0, bh = 0;         // buffer
  std::size_t stride = 0;
  std::int32_t bin = 32;  // buffer pixels per bin side
  std::int32_t bins_x = 0, bins_y = 0;
  float clear_key = 1;
  std::uint64_t frame_triangles = 0;  // triangles of the occluders selected this frame
  std::uint32_t stamp = 0;
  std::vector<float> keys;  // per pixel (Representation::PerPixel)
  bool masked = false;
  std::vector<detail::MaskedBlock> blocks;  // Representation::Masked
  std::size_t blocks_per_row = 0;
  std::vector<Bin> bins;
  std::vector<PendingObject> pending;
  std::vector<detail::RasterTriangle> tris;  // [0, tri_count) this frame (never shrunk)
  std::size_t tri_count = 0;
  detail::TriangleSetup setup;

  // Workers (desc.threads > 0): drawObject() posts each object to the pool to be set up
  // and binned (setUpTask); drain() waits for that and then rasterises the requested
  // bins with triangles waiting, one bin per task (rasterTask). The caller reads keys
  // only after drain(), when no task runs. Declared after what the tasks use, destroyed
  // before it.
  std::vector<Worker> workers;
  std::deque<Handed> handed;         // this frame's objects, in draw order
  bool posted = false;               // set-ups posted since the pool's last wait()
  std::vector<std::uint32_t> dirty;  // bins the raster tasks take, by index
  std::unique_ptr<detail::WorkerPool> pool;

  static void setUpTask(void* handed_object, std::uint32_t worker, std::size_t);
  static void rasterTask(void* impl, std::uint32_t worker, std::size_t i);
  void setUpOn(Worker& w, const Handed& h);
  void rasterizeBinOn(Worker& w, std::uint32_t index);
  // Waits for the workers' set-ups; with `rect` (buffer pixels), then rasterises the bins
  // under it that they left triangles in. Adds what the workers counted to `stats`.
  void drain(const PixelRect* rect);
  void clearBinIfStale(Bin& b, std::int32_t bx, std::int32_t by);

  Status begin(const Camera& camera);
  void draw(std::uint32_t id, const ObjectTransform* transform);
  // Brings every buffer pixel under the viewport rectangle up to date.
  void ensure(const PixelRect& rect);
  void setUpObject(const PendingObject& p);
  void rasterizeBin(std::int32_t bx, std::int32_t by);
  // Runs the kernel of the representation over triangles tris[list[0..n)] in bin (bx, by).
  void rasterizeList(const detail::RasterTriangle* t, const std::uint32_t* list, std::size_t n,
                     Bin& b, std::int32_t bx, std::int32_t by);
  // A buffer pixel's key (either representation).
  float keyAt(std::int32_t i, std::int32_t j) const {
    if (!masked) return keys[std::size_t(j) * stride + std::size_t(i)];
    const detail::MaskedBlock& b =
        blocks[std::size_t(j / detail::kMaskH) * blocks_per_row + std::size_t(i / detail::kMaskW)];
    const int bit = (j % detail::kMaskH) * detail::kMaskW + i % detail::kMaskW;
    return (b.mask >> bit) & 1u ? b.z_layer : b.z_far;
  }
  // Masked: calls visit(key, weight) for the pixels of buffer rectangle `b` that share a
  // key in a block, weight = the viewport pixels of `r` they cover.
  template <class Visit>
  void visitMasked(const PixelRect& r, const PixelRect& b, Visit visit) const;
  PixelRect bufferRect(const PixelRect& r) const {
    return {r.x0 / scale, r.y0 / scale, (r.x1 + scale - 1) / scale, (r.y1 + scale - 1) / scale};
  }
  // Viewport pixels of `r` that buffer column i (row j) covers.
  std::int32_t spanX(const PixelRect& r, std::int32_t i) const {
    return std::min(r.x1, (i + 1) * scale) - std::max(r.x0, i * scale);
  }
  std::int32_t spanY(const PixelRect& r, std::int32_t j) const {
    return std::min(r.y1, (j + 1) * scale) - std::max(r.y0, j * scale);
  }
  AreaDepth summary(const PixelRect& r);
  std::uint32_t count(const PixelRect& r, float threshold);
};

Status OcclusionBuffer::Impl::begin(const Camera& camera) {
  drain(nullptr);  // workers leave the buffer alone from here
  Result<Projector> checked = Projector::create(camera, desc.projection);  // the camera
  if (!checked) return checked.status();
  projector.emplace(std::move(checked).value());
  const Mat4d& m = camera.view_projection;
  for (int i = 0; i < 16; ++i) frame.m[i] = m.m[i];
  const Mat4d render = multiply(camera.view_projection, translation(camera.render_origin));
  for (int i = 0; i < 16; ++i) frame.render_abs[i] = std::fabs(render.m[i]);
  for (int r = 0; r < 4; ++r) {
    frame.clip_abs[r] = std::fabs(m.m[r]) + std::fabs(m.m[4 + r]) + std::fabs(m.m[8 + r]);
  }
  frame.origin[0] = camera.render_origin.x;
  frame.origin[1] = camera.render_origin.y;
  frame.origin[2] = camera.render_origin.z;
  frame.render_k = desc.projection.render_error_ulps * kUnitRoundoff;
  frame.quantisation = quantisationStep(camera.depth.format) * desc.projection.quantisation_scale;
  frame.half_w = 0.5 * camera.width;
  frame.half_h = 0.5 * camera.height;
  const bool reversed = camera.depth.convention == DepthConvention::Reversed;
  const bool zero_to_one = camera.depth.clip_range == ClipDepthRange::ZeroToOne;
  const double sign = reversed ? -1.0 : 1.0;
  frame.key_scale = sign * (zero_to_one ? 1.0 : 0.5);
  frame.key_offset = sign * (zero_to_one ? 0.0 : 0.5);
  frame.near_key = projector->nearKey();
  frame.clear_key = projector->clearKey();
  clear_key = projector->clearKey();
  scale = std::int32_t(desc.resolution);
  frame.scale = scale;
  frame.inv_scale = 1.0 / scale;
  // A multisampled renderer (Camera::multisample) samples anywhere in the pixel, not at
  // its centre: every sample lies within half a pixel of it, so a pixel's samples spread
  // over the square of half-width 0.5 around the centre, which widens each buffer
  // pixel's spread by as much (a claim then holds for every sample, as the resolvers'
  // farthest sample needs; see the header, "Resolution").
  frame.radius = 0.5 * (scale - 1) + (camera.multisample ? 0.5 : 0.0);
  frame.skip_closed_back_faces = !desc.closed_back_faces;
  frame.exact_coverage = desc.unsafe_exact_coverage;
  frame.exact_depth = desc.unsafe_exact_depth;
  // A vertex snaps by up to one sub-pixel step per axis if the rasteriser truncates
  // (projection.hpp widens box rectangles by half a step, for rounding).
  const int bits = desc.projection.subpixel_bits;
  snap_half = bits >= 16 ? 0.0 : std::ldexp(0.5, -bits);
  frame.snap = 2 * snap_half;

  width = std::int32_t(camera.width);
  height = std::int32_t(camera.height);
  const std::int32_t new_bw = (width + scale - 1) / scale, new_bh = (height + scale - 1) / scale;
  bin = std::max(8, kBinViewport / scale);
  const bool new_masked = desc.representation == Representation::Masked;
  if (new_bw != bw || new_bh != bh || new_masked != masked) {
    masked = new_masked;
    bw = new_bw;
    bh = new_bh;
    bins_x = (bw + bin - 1) / bin;
    bins_y = (bh + bin - 1) / bin;
    stride = std::size_t(bins_x) * std::size_t(bin);  // whole bins: 8-wide stores stay inside
    if (masked) {
      keys.clear();
      blocks_per_row = stride / detail::kMaskW;
      blocks.assign(blocks_per_row * std::size_t(bins_y) * std::size_t(bin / detail::kMaskH), {});
    } else {
      blocks.clear();
      keys.assign(stride * std::size_t(bins_y) * std::size_t(bin), clear_key);
    }
    bins.assign(std::size_t(bins_x) * std::size_t(bins_y), Bin{});
    for (Worker& w : workers) w.bin_entries.assign(bins.size(), {});
    stamp = 0;
  }
  frame.buffer_w = bw;
  frame.buffer_h = bh;
  ++stamp;
  if (stamp == 0) {  // wrapped: every bin must be cleared again
    for (Bin& b : bins) b.stamp = 0;
    stamp = 1;
  }
  for (Bin& b : bins) b.pending.clear();
  pending.clear();
  handed.clear();
  for (Worker& w : workers) {
    w.tri_count = 0;
    for (std::vector<Entry>& e : w.bin_entries) e.clear();
  }
  tri_count = 0;
  frame_triangles = 0;
  in_frame = true;
  return {};
}

void OcclusionBuffer::Impl::draw(std::uint32_t id, const ObjectTransform* transform) {
  ++stats.objects_drawn;
  stats.objects_moved += transform != nullptr;
  // Where GL draws the object: its box, placed if it moves.
  auto drawnBox = [&](std::uint32_t o) {
    const Aabb& box = meshes.object(o).box;
    return transform ? placedBox(box, *transform, placementPad(box, *transform)) : box;
  };
  // A model inside its object holds only while the object lies wholly beyond the near
  // plane (the eye is then outside it and GL does not clip it).
  BoxProjection p = projector->project(drawnBox(id));
  const bool model = meshes.object(id).inside_solid;
  for (int hops = 0; meshes.object(id).inside_solid && p.cls != ProjectionClass::Inside; ++hops) {
    const std::uint32_t fallback = meshes.object(id).fallback;
    if (fallback == kNoOccluder || hops > 8) {
      ++stats.objects_skipped;
      return;
    }
    ++stats.objects_fallback;
    id = fallback;
    p = projector->project(drawnBox(id));
  }
  if (p.cls == ProjectionClass::Outside || p.cls == ProjectionClass::Invalid ||
      meshes.object(id).triangle_count == 0) {
    ++stats.objects_skipped;
    return;
  }
  // Selection: screen pixels per triangle, then the frame's budget.
  const std::uint64_t triangles = meshes.object(id).triangle_count;
  const double pixels = double(p.rect.x1 - p.rect.x0) * double(p.rect.y1 - p.rect.y0);
  if (pixels < desc.min_pixels_per_triangle * double(triangles) ||
      (desc.triangle_budget > 0 && frame_triangles + triangles > desc.triangle_budget)) {
    ++stats.objects_unselected;
    return;
  }
  frame_triangles += triangles;
  stats.triangles_selected += triangles;
  PendingObject po;
  po.object.occluder = id;
  if (transform) {
    po.object.moved = true;
    std::copy(std::begin(transform->rotation), std::end(transform->rotation), po.object.rotation);
    po.object.translation[0] = transform->translation.x;
    po.object.translation[1] = transform->translation.y;
    po.object.translation[2] = transform->translation.z;
    po.object.pad = placementPad(meshes.object(id).box, *transform);
    po.object.orientation = orientation(transform->rotation);
  }
  if (model && meshes.object(id).inside_solid) {
    // GL draws the object's vertices, not the model's: bound them by the object's box.
    po.object.s_x = double(p.widen_x) + snap_half;
    po.object.s_y = double(p.widen_y) + snap_half;
    po.object.margin = p.margin;
  }
  po.rect = p.rect;
  if (!pool) {
    pending.push_back(po);
    return;
  }
  handed.push_back({this, po, std::uint32_t(handed.size())});
  pool->post(&Impl::setUpTask, &handed.back(), 0);
  posted = true;
}

void OcclusionBuffer::Impl::setUpTask(void* handed_object, std::uint32_t worker, std::size_t) {
  const Handed& h = *static_cast<const Handed*>(handed_object);
  h.impl->setUpOn(h.impl->workers[worker], h);
}

void OcclusionBuffer::Impl::setUpOn(Worker& w, const Handed& h) {
  const std::size_t first = w.tri_count;
  w.counted.triangles_set_up += w.setup.run(frame, meshes, h.object.object, w.tris, w.tri_count);
  ++w.counted.objects_set_up;
  for (std::size_t t = first; t < w.tri_count; ++t) {
    const detail::RasterTriangle& rt = w.tris[t];
    for (std::int32_t by = rt.y0 / bin; by <= (rt.y1 - 1) / bin; ++by) {
      for (std::int32_t bx = rt.x0 / bin; bx <= (rt.x1 - 1) / bin; ++bx) {
        w.bin_entries[std::size_t(by) * std::size_t(bins_x) + std::size_t(bx)].push_back(
            {h.seq, std::uint32_t(t)});
      }
    }
  }
}

void OcclusionBuffer::Impl::rasterTask(void* impl, std::uint32_t worker, std::size_t i) {
  Impl& m = *static_cast<Impl*>(impl);
  m.rasterizeBinOn(m.workers[worker], m.dirty[i]);
}

void OcclusionBuffer::Impl::rasterizeBinOn(Worker& w, std::uint32_t index) {
  const std::int32_t bx = std::int32_t(index) % bins_x, by = std::int32_t(index) / bins_x;
  Bin& b = bins[index];
  clearBinIfStale(b, bx, by);
  // The workers' entries for this bin merged in draw order (each worker's are ascending):
  // every worker count lands the same triangles on the bin in the same order, so the
  // masked blocks, whose keys depend on it, come out the same too.
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  w.cursor.assign(workers.size(), 0);
  for (;;) {
    std::size_t first = workers.size();
    std::uint32_t first_seq = kNone, next_seq = kNone;
    for (std::size_t k = 0; k < workers.size(); ++k) {
      const std::vector<Entry>& e = workers[k].bin_entries[index];
      if (w.cursor[k] == e.size()) continue;
      const std::uint32_t s = e[w.cursor[k]].seq;
      if (s < first_seq) {
        next_seq = first_seq;
        first_seq = s;
        first = k;
      } else if (s < next_seq) {
        next_seq = s;
      }
    }
    if (first == workers.size()) break;
    // The run of that worker's entries drawn before any other worker's next.
    const std::vector<Entry>& e = workers[first].bin_entries[index];
    w.list.clear();
    for (std::size_t& c = w.cursor[first]; c < e.size() && e[c].seq < next_seq; ++c) {
      w.list.push_back(e[c].tri);
    }
    rasterizeList(workers[first].tris.data(), w.list.data(), w.list.size(), b, bx, by);
    w.counted.triangles_rasterized += w.list.size();
  }
  for (Worker& k : workers) k.bin_entries[index].clear();
  ++w.counted.tiles_rasterized;
}

void OcclusionBuffer::Impl::drain(const PixelRect* rect) {
  if (!pool) return;
  const auto start = Clock::now();
  // Most requests come with nothing to do (the grid asks hundreds of times a frame):
  // those take neither the pool's lock nor a worker.
  if (posted) {
    pool->wait();
    posted = false;
  }
  if (rect) {
    dirty.clear();
    for (std::int32_t by = rect->y0 / bin; by <= (rect->y1 - 1) / bin; ++by) {
      for (std::int32_t bx = rect->x0 / bin; bx <= (rect->x1 - 1) / bin; ++bx) {
        const std::uint32_t i = std::uint32_t(by * bins_x + bx);
        for (const Worker& w : workers) {
          if (!w.bin_entries[i].empty()) {
            dirty.push_back(i);
            break;
          }
        }
      }
    }
    if (dirty.size() == 1) {
      rasterTask(this, pool->size(), 0);  // in the caller's slot: no task is running
    } else if (dirty.size() > 1) {
      pool->forEach(dirty.size(), &Impl::rasterTask, this);
    }
  }
  for (Worker& w : workers) {
    stats.objects_set_up += w.counted.objects_set_up;
    stats.triangles_set_up += w.counted.triangles_set_up;
    stats.triangles_rasterized += w.counted.triangles_rasterized;
    stats.tiles_rasterized += w.counted.tiles_rasterized;
    w.counted = OcclusionBufferStats{};
  }
  stats.worker_seconds = pool->busySeconds();
  stats.wait_seconds += secondsSince(start);
}

void OcclusionBuffer::Impl::setUpObject(const PendingObject& p) {
  const std::size_t first = tri_count;
  stats.triangles_set_up += setup.run(frame, meshes, p.object, tris, tri_count);
  ++stats.objects_set_up;
  for (std::size_t t = first; t < tri_count; ++t) {
    const detail::RasterTriangle& rt = tris[t];
    const std::int32_t bx0 = rt.x0 / bin, bx1 = (rt.x1 - 1) / bin;
    const std::int32_t by0 = rt.y0 / bin, by1 = (rt.y1 - 1) / bin;
    for (std::int32_t by = by0; by <= by1; ++by) {
      for (std::int32_t bx = bx0; bx <= bx1; ++bx) {
        bins[std::size_t(by) * std::size_t(bins_x) + std::size_t(bx)].pending.push_back(
            std::uint32_t(t));
      }
    }
  }
}

void OcclusionBuffer::Impl::clearBinIfStale(Bin& b, std::int32_t bx, std::int32_t by) {
  const std::int32_t x0 = bx * bin, y0 = by * bin;
  if (b.stamp != stamp && masked) {
    detail::MaskedBlock clear_block;
    clear_block.z_layer = -HUGE_VALF;
    clear_block.z_far = clear_key;
    for (std::int32_t y = y0 / detail::kMaskH; y < (y0 + bin) / detail::kMaskH; ++y) {
      std::fill_n(blocks.begin() + std::ptrdiff_t(std::size_t(y) * blocks_per_row +
                                                  std::size_t(x0 / detail::kMaskW)),
                  bin / detail::kMaskW, clear_block);
    }
    b.stamp = stamp;
  } else if (b.stamp != stamp) {
    for (std::int32_t y = y0; y < y0 + bin; ++y) {
      std::fill_n(keys.begin() + std::ptrdiff_t(std::size_t(y) * stride + std::size_t(x0)), bin,
                  clear_key);
    }
    b.stamp = stamp;
    const std::size_t side = std::size_t(bin / detail::kBlockSide);
    b.block_max.assign(side * side, clear_key);
  }
}

void OcclusionBuffer::Impl::rasterizeList(const detail::RasterTriangle* t,
                                          const std::uint32_t* list, std::size_t n, Bin& b,
                                          std::int32_t bx, std::int32_t by) {
  detail::RasterTarget target;
  target.keys = keys.data();
  target.stride = stride;
  target.x0 = bx * bin;
  target.y0 = by * bin;
  target.x1 = std::min(target.x0 + bin, bw);
  target.y1 = std::min(target.y0 + bin, bh);
  target.scale = float(scale);
  target.half = 0.5f * float(scale);
  target.block_max = b.block_max.data();
  if (!masked) {
    kernels.raster(t, list, n, target);
    return;
  }
  detail::MaskedTarget m;
  m.tile = target;
  m.blocks = blocks.data();
  m.blocks_per_row = blocks_per_row;
  m.unsafe_merge = desc.unsafe_masked_merge;
  kernels.masked(t, list, n, m);
}

void OcclusionBuffer::Impl::rasterizeBin(std::int32_t bx, std::int32_t by) {
  Bin& b = bins[std::size_t(by) * std::size_t(bins_x) + std::size_t(bx)];
  clearBinIfStale(b, bx, by);
  if (b.pending.empty()) return;
  rasterizeList(tris.data(), b.pending.data(), b.pending.size(), b, bx, by);
  stats.triangles_rasterized += b.pending.size();
  ++stats.tiles_rasterized;
  b.pending.clear();
}

void OcclusionBuffer::Impl::ensure(const PixelRect& rect) {
  const PixelRect buffer_rect = bufferRect(rect);
  drain(&buffer_rect);
  // In the order drawn (roughly front to back): a masked block's keys depend on the order
  // triangles land in, and near triangles first let the kernels skip more of the rest.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < pending.size(); ++i) {
    if (pending[i].rect.meets(rect)) {
      setUpObject(pending[i]);
    } else {
      pending[kept++] = pending[i];
    }
  }
  pending.resize(kept);
  const PixelRect b = bufferRect(rect);
  for (std::int32_t by = b.y0 / bin; by <= (b.y1 - 1) / bin; ++by) {
    for (std::int32_t bx = b.x0 / bin; bx <= (b.x1 - 1) / bin; ++bx) rasterizeBin(bx, by);
  }
}

template <class Visit>
void OcclusionBuffer::Impl::visitMasked(const PixelRect& r, const PixelRect& b, Visit visit) const {
  using detail::kMaskH;
  using detail::kMaskW;
  for (std::int32_t by = b.y0 / kMaskH; by <= (b.y1 - 1) / kMaskH; ++by) {
    const std::int32_t ya = std::max(b.y0, by * kMaskH), yb = std::min(b.y1, by * kMaskH + kMaskH);
    for (std::int32_t bx = b.x0 / kMaskW; bx <= (b.x1 - 1) / kMaskW; ++bx) {
      const std::int32_t xa = std::max(b.x0, bx * kMaskW),
                         xb = std::min(b.x1, bx * kMaskW + kMaskW);
      const std::uint32_t row_bits = ((1u << (xb - xa)) - 1u) << (xa - bx * kMaskW);
      std::uint32_t in_rect = 0;
      for (std::int32_t y = ya; y < yb; ++y) in_rect |= row_bits << ((y - by * kMaskH) * kMaskW);
      const detail::MaskedBlock& k = blocks[std::size_t(by) * blocks_per_row + std::size_t(bx)];
      const std::uint32_t groups[2] = {in_rect & k.mask, in_rect & ~k.mask};
      const float group_keys[2] = {k.z_layer, k.z_far};
      for (int g = 0; g < 2; ++g) {
        if (groups[g] == 0) continue;
        if (scale == 1) {
          visit(group_keys[g], std::uint64_t(std::bitset<32>(groups[g]).count()));
          continue;
        }
        std::uint64_t weight = 0;
        for (int bit = 0; bit < kMaskW * kMaskH; ++bit) {
          if (!((groups[g] >> bit) & 1u)) continue;
          weight += std::uint64_t(spanX(r, bx * kMaskW + bit % kMaskW)) *
                    std::uint64_t(spanY(r, by * kMaskH + bit / kMaskW));
        }
        visit(group_keys[g], weight);
      }
    }
  }
}

AreaDepth OcclusionBuffer::Impl::summary(const PixelRect& r) {
  ensure(r);
  const PixelRect b = bufferRect(r);
  if (masked) {
    AreaDepth out;
    out.min_key = HUGE_VALF;
    out.max_key = -HUGE_VALF;
    std::uint64_t free_pixels = 0;
    visitMasked(r, b, [&](float key, std::uint64_t weight) {
      out.min_key = std::min(out.min_key, key);
      out.max_key = std::max(out.max_key, key);
      if (!(key < clear_key)) free_pixels += weight;
    });
    out.free_pixels = std::uint32_t(free_pixels);
    return out;
  }
  const detail::KeyRange range =
      kernels.range(keys.data(), stride, b.x0, b.y0, b.x1, b.y1, clear_key);
  AreaDepth out;
  out.min_key = range.min_key;
  out.max_key = range.max_key;
  if (scale == 1 || range.at_or_beyond == 0) {
    out.free_pixels = range.at_or_beyond;
    return out;
  }
  // Coarse: weigh each free block by the viewport pixels of `r` it covers.
  std::uint64_t free_pixels = 0;
  for (std::int32_t j = b.y0; j < b.y1; ++j) {
    const float* row = keys.data() + std::size_t(j) * stride;
    for (std::int32_t i = b.x0; i < b.x1; ++i) {
      if (!(row[i] < clear_key)) {
        free_pixels += std::uint64_t(spanX(r, i)) * std::uint64_t(spanY(r, j));
      }
    }
  }
  out.free_pixels = std::uint32_t(free_pixels);
  return out;
}

std::uint32_t OcclusionBuffer::Impl::count(const PixelRect& r, float threshold) {
  ensure(r);
  const PixelRect b = bufferRect(r);
  if (masked) {
    std::uint64_t n = 0;
    visitMasked(r, b, [&](float key, std::uint64_t weight) {
      if (!(key < threshold)) n += weight;
    });
    return std::uint32_t(n);
  }
  if (scale == 1) {
    return kernels.range(keys.data(), stride, b.x0, b.y0, b.x1, b.y1, threshold).at_or_beyond;
  }
  std::uint64_t n = 0;
  for (std::int32_t j = b.y0; j < b.y1; ++j) {
    const float* row = keys.data() + std::size_t(j) * stride;
    std::uint64_t in_row = 0;
    for (std::int32_t i = b.x0; i < b.x1; ++i) {
      // NaN never occurs (the setup drops non-finite triangles); count it if it did.
      if (!(row[i] < threshold)) in_row += std::uint64_t(spanX(r, i));
    }
    n += in_row * std::uint64_t(spanY(r, j));
  }
  return std::uint32_t(n);
}

Result<std::unique_ptr<OcclusionBuffer>> OcclusionBuffer::create(const OccluderMeshes& meshes,
                                                                 const OcclusionBufferDesc& desc) {
  std::string problem = validateOcclusionBufferDesc(desc);
  if (!problem.empty()) return Status(ErrorCode::InvalidArgument, std::move(problem));
  return std::unique_ptr<OcclusionBuffer>(new OcclusionBuffer(Checked{}, meshes, desc));
}

OcclusionBuffer::OcclusionBuffer(Checked, const OccluderMeshes& meshes,
                                 const OcclusionBufferDesc& desc)
    : impl_(std::make_unique<Impl>(meshes, desc)), desc_(desc) {}

OcclusionBuffer::~OcclusionBuffer() = default;

Isa OcclusionBuffer::isa() const { return impl_->isa; }

const OcclusionBufferStats& OcclusionBuffer::stats() const { return impl_->stats; }

Status OcclusionBuffer::beginFrame(const Camera& camera) {
  const auto start = Clock::now();
  Status begun = impl_->begin(camera);
  impl_->stats.seconds += secondsSince(start);
  return begun;
}

Status OcclusionBuffer::endFrame() {
  impl_->drain(nullptr);  // the workers' counts belong to this frame
  impl_->in_frame = false;
  return {};
}

Status OcclusionBuffer::tryDrawObject(std::uint32_t id) { return drawChecked(id, nullptr); }

Status OcclusionBuffer::tryDrawObject(std::uint32_t id, const ObjectTransform& transform) {
  bool finite = std::isfinite(transform.translation.x) && std::isfinite(transform.translation.y) &&
                std::isfinite(transform.translation.z);
  for (double e : transform.rotation) finite = finite && std::isfinite(e);
  if (!finite) {
    std::ostringstream out;
    out << "OcclusionBuffer::drawObject: object " << id
        << " has a transform that is not finite; give every rotation element and the "
           "translation a finite value";
    return Status(ErrorCode::InvalidArgument, out.str());
  }
  return drawChecked(id, &transform);
}

Status OcclusionBuffer::drawChecked(std::uint32_t id, const ObjectTransform* transform) {
  if (!impl_->in_frame) {
    return Status(ErrorCode::InvalidArgument,
                  "OcclusionBuffer::drawObject: call it between beginFrame() and endFrame()");
  }
  if (id >= impl_->meshes.objectCount()) {
    std::ostringstream out;
    out << "OcclusionBuffer::drawObject: object " << id << " is not in the occluder meshes ("
        << impl_->meshes.objectCount() << " objects)";
    return Status(ErrorCode::InvalidArgument, out.str());
  }
  const auto start = Clock::now();
  impl_->draw(id, transform);
  impl_->stats.seconds += secondsSince(start);
  return {};
}

void OcclusionBuffer::submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) {
  const auto start = Clock::now();
  for (std::size_t i = 0; i < count; ++i) {
    const AreaRequest& r = requests[i];
    if (r.ask == AreaAsk::Summary) {
      answers[i].depth = impl_->summary(r.rect);
    } else {
      answers[i].count = impl_->count(r.rect, r.threshold);
    }
    counters_.pixels += std::uint64_t(r.rect.area());
  }
  counters_.reads += count;
  counters_.batches += count > 0;
  const double s = secondsSince(start);
  counters_.seconds += s;
  impl_->stats.seconds += s;
}

void OcclusionBuffer::readKeys(const PixelRect& rect, float* keys) {
  const auto start = Clock::now();
  Impl& m = *impl_;
  m.ensure(rect);
  std::size_t o = 0;
  for (std::int32_t y = rect.y0; y < rect.y1; ++y) {
    for (std::int32_t x = rect.x0; x < rect.x1; ++x) keys[o++] = m.keyAt(x / m.scale, y / m.scale);
  }
  counters_.reads += 1;
  counters_.pixels += std::uint64_t(rect.area());
  const double s = secondsSince(start);
  counters_.seconds += s;
  m.stats.seconds += s;
}

}  // namespace logrid::cpu
