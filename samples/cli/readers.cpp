#include "cli/readers.hpp"

#include <optional>

#include "cli/cpu_reader.hpp"
#include "logrid/cpu/software_depth.hpp"
#include "logrid/cpu/software_rasterizer.hpp"
#include "logrid/zread/gl_sources.hpp"
#include "logrid/zread/reduction_source.hpp"

namespace logrid::samples {
namespace {

// A GL source over the frame's framebuffer.
template <typename Source>
class GlReader final : public FrameReader {
 public:
  template <typename... Args>
  explicit GlReader(std::uint32_t framebuffer, Args... args) : source_(framebuffer, args...) {}
  DepthSource& source() override { return source_; }

 private:
  Source source_;
};

// readpixels for an application that keeps its own GL state (GlStatePolicy::
// ApplicationManaged): nothing saved or restored, so the runner sets its state again.
class ManagedReader final : public FrameReader {
 public:
  explicit ManagedReader(std::uint32_t framebuffer)
      : source_(framebuffer, zread::GlStatePolicy::ApplicationManaged) {}
  DepthSource& source() override { return source_; }
  bool leavesGlState() const override { return true; }

 private:
  zread::ReadPixelsSource source_;
};

// readpixels with the GL state saved, checked and restored around every read, as every
// read did before the culler opened one access window per batch (gl_state.hpp): the
// source's beginAccess() and endAccess() are not passed on. For comparison only.
class PerReadSource final : public DepthSource, public KeyReader {
 public:
  explicit PerReadSource(std::uint32_t framebuffer) : inner_(framebuffer) {}
  DepthSourceTraits traits() const override { return inner_.traits(); }
  Status beginFrame(const Camera& camera) override { return inner_.beginFrame(camera); }
  Status endFrame() override { return inner_.endFrame(); }
  // Errors are checked around every read, outside any window: they are the inner source's.
  Status endAccess() override { return inner_.takeError(); }
  void noteDraw() override { inner_.noteDraw(); }
  void submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) override {
    inner_.submit(requests, count, answers);
    counters_ = inner_.counters();
  }
  void collect() override {
    inner_.collect();
    counters_ = inner_.counters();
  }
  void readKeys(const PixelRect& rect, float* keys) override {
    inner_.readKeys(rect, keys);
    counters_ = inner_.counters();
  }

 private:
  zread::ReadPixelsSource inner_;
};

class PerReadReader final : public FrameReader {
 public:
  explicit PerReadReader(std::uint32_t framebuffer) : source_(framebuffer) {}
  DepthSource& source() override { return source_; }

 private:
  PerReadSource source_;
};

// A software depth buffer fed with the triangles of every object drawn, rasterised
// with inner coverage: it must never hold depth where GL drew nothing.
class SoftwareReader final : public FrameReader {
 public:
  explicit SoftwareReader(const ReaderContext& c)
      : scene_(c.scene), motion_(c.motion), buffer_(c.width, c.height, c.depth.convention) {}
  DepthSource& source() override { return buffer_; }
  void beginFrame(const Camera& camera) override {
    buffer_.clear();
    raster_.emplace(camera, buffer_, nullptr, cpu::Coverage::Inner);
  }
  void objectDrawn(ObjectId id) override {
    const gl::RenderMesh& mesh = scene_.mesh;
    const gl::RenderMesh::Draw& d = mesh.draws[id];
    // A mover's vertices where the renderer puts them (in double, rounded once).
    const RigidTransform* t = nullptr;
    if (motion_ && id >= scene_.static_objects &&
        id - scene_.static_objects < motion_->transforms.size()) {
      t = &motion_->transforms[id - scene_.static_objects];
    }
    float moved[3][3];
    for (std::uint32_t i = d.first_index; i < d.first_index + d.index_count; i += 3) {
      const float* v[3];
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t local =
            mesh.indices16.empty() ? mesh.indices32[i + k] : mesh.indices16[i + k];
        v[k] = &mesh.positions[(std::size_t(d.base_vertex) + local) * 3];
        if (t) {
          const double tr[3] = {t->translation.x, t->translation.y, t->translation.z};
          for (int r = 0; r < 3; ++r) {
            moved[k][r] =
                static_cast<float>(t->rotation[r] * v[k][0] + t->rotation[3 + r] * v[k][1] +
                                   t->rotation[6 + r] * v[k][2] + tr[r]);
          }
          v[k] = moved[k];
        }
      }
      raster_->drawTriangle(v[0], v[1], v[2], id);
    }
  }

 private:
  const PreparedScene& scene_;
  const MotionFrame* motion_;
  cpu::SoftwareDepthBuffer buffer_;
  std::optional<cpu::SoftwareRasterizer> raster_;
};

}  // namespace

const std::vector<ReaderInfo>& readerTable() {
  static const std::vector<ReaderInfo> table = {
      {"readpixels", "glReadPixels, synchronous, one read per rectangle (the default)", true, true,
       [](const ReaderContext& c) {
         return std::make_unique<GlReader<zread::ReadPixelsSource>>(c.framebuffer);
       }},
      {"readpixels-managed",
       "readpixels for an application that manages its GL state (GlStatePolicy::"
       "ApplicationManaged): nothing saved or restored",
       true, true,
       [](const ReaderContext& c) { return std::make_unique<ManagedReader>(c.framebuffer); }},
      {"readpixels-per-read",
       "readpixels with the GL state saved and restored around every read instead of once "
       "per batch (for comparison)",
       true, true,
       [](const ReaderContext& c) { return std::make_unique<PerReadReader>(c.framebuffer); }},
      {"pbo", "a ring of pixel-buffer objects with fences: one wait per batch", true, true,
       [](const ReaderContext& c) {
         return std::make_unique<GlReader<zread::PboSource>>(c.framebuffer);
       }},
      {"reduce", "a compute shader reduces each rectangle to 16 bytes on the GPU", true, true,
       [](const ReaderContext& c) {
         return std::make_unique<GlReader<zread::ReductionSource>>(c.framebuffer);
       }},
      {"query", "hardware occlusion queries (GL_SAMPLES_PASSED), counts only", false, true,
       [](const ReaderContext& c) {
         return std::make_unique<GlReader<zread::QuerySource>>(c.framebuffer);
       }},
      {"software", "a scalar CPU depth buffer fed with the drawn triangles", true, false,
       [](const ReaderContext& c) { return std::make_unique<SoftwareReader>(c); }},
      {"cpu", "the conservative CPU occlusion buffer fed with each drawn object's occluder", true,
       false, [](const ReaderContext& c) { return makeCpuReader(c); }},
  };
  return table;
}

const ReaderInfo* findReader(const std::string& name) {
  for (const ReaderInfo& r : readerTable()) {
    if (name == r.name) return &r;
  }
  return nullptr;
}

std::string readerNames() {
  std::string out;
  for (const ReaderInfo& r : readerTable()) {
    if (!out.empty()) out += ", ";
    out += r.name;
  }
  return out;
}

}  // namespace logrid::samples
