// The soak run (scripts/soak.sh; not part of CI): many thousands of frames, each checked
// against the object-ID oracle, over random scenes and settings in one process, to find
// rare misses and memory that grows.
//
// Each run picks, from a seeded generator: a scene (the forest or the city at a small
// scale with a random seed, or a model file: a small forest written as OBJ and read back
// through the assimp loader, walked on the loader's orbit), a size, a tile size, a depth format and
// convention, a method, a reader, a sample count, and walks `--frames-per-run` frames of the
// scene's path. Every visible object must be drawn (misses and missed depth-extrapolation artifacts
// both fail the run). Scenes are generated, uploaded and released per run.
//
// Memory: after a warm-up that visits the largest configuration of each scene kind, the
// resident set's high-water mark (VmHWM) is recorded as the start figure; at the end it
// is recorded again, with the resident set (VmRSS) after each run. Flat memory means the
// end peak equals the start peak up to allocator noise.
//
// Usage: logrid_soak [--frames N] [--frames-per-run K] [--seed S] [--json FILE]
// Exit status 0 when no visible object was missed, 1 otherwise, 2 for bad usage.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli/frame_runner.hpp"
#include "logrid/error.hpp"
#include "logrid/gl/context.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "scene/generators.hpp"
#include "scene/loader.hpp"
#include "scene/prepare.hpp"
#include "scene/view.hpp"

namespace {

using namespace logrid;
using namespace logrid::samples;

std::uint64_t statusKiB(const char* field) {
  std::ifstream status("/proc/self/status");
  const std::string key = std::string(field) + ":";
  for (std::string line; std::getline(status, line);) {
    if (line.rfind(key, 0) == 0) return std::stoull(line.substr(key.size()));
  }
  return 0;
}

// A scene as an OBJ file, one "o" per object (what a user's model file looks like).
void writeObj(const Scene& scene, const std::string& path) {
  std::ofstream out(path);
  out.precision(9);
  for (std::size_t v = 0; v + 2 < scene.positions.size(); v += 3) {
    out << "v " << scene.positions[v] << " " << scene.positions[v + 1] << " "
        << scene.positions[v + 2] << "\n";
  }
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    const SceneObject& obj = scene.objects[o];
    out << "o object" << o << "\n";
    for (std::uint32_t i = obj.first_index; i + 2 < obj.first_index + obj.index_count; i += 3) {
      out << "f " << scene.indices[i] + 1 << " " << scene.indices[i + 1] + 1 << " "
          << scene.indices[i + 2] + 1 << "\n";
    }
  }
  if (!out) throw Error(ErrorCode::Environment, "soak: cannot write " + path);
}

struct Run {
  std::string scene;  // forest, city or model
  double scale = 0.05;
  std::uint64_t seed = 1;
  std::uint32_t width = 160, height = 120, tile = 32, samples = 0;
  DepthFormat format = DepthFormat::D32F;
  DepthConvention convention = DepthConvention::Standard;
  Method method = Method::LogState;
  std::string reader = "readpixels";

  std::string describe() const {
    std::ostringstream out;
    out << scene << " scale " << scale << " seed " << seed << ", " << width << "x" << height
        << " tile " << tile << ", " << toString(format) << " " << toString(convention) << ", "
        << toString(method) << " / " << reader << ", samples " << samples;
    return out.str();
  }
};

template <typename T>
T pick(std::mt19937_64& rng, std::initializer_list<T> values) {
  return *(values.begin() + std::uniform_int_distribution<std::size_t>(0, values.size() - 1)(rng));
}

Run randomRun(std::mt19937_64& rng) {
  Run r;
  r.scene = pick<std::string>(rng, {"forest", "forest", "city", "city", "model"});
  std::uniform_real_distribution<double> unit(0, 1);
  r.scale = r.scene == "city" ? 0.004 + 0.012 * unit(rng) : 0.02 + 0.08 * unit(rng);
  r.seed = 1 + rng() % 1000;
  r.width = pick(rng, {64u, 97u, 160u, 200u, 320u});
  r.height = pick(rng, {48u, 61u, 120u, 150u, 240u});
  r.tile = pick(rng, {3u, 8u, 16u, 32u, 32u, 64u, 200u});
  r.format = pick(rng, {DepthFormat::D16, DepthFormat::D24, DepthFormat::D32F});
  r.convention = pick(rng, {DepthConvention::Standard, DepthConvention::Reversed});
  r.method = pick(
      rng, {Method::LogState, Method::LogZfar, Method::Bog, Method::Hzb, Method::Pq, Method::Vfc});
  r.reader = pick<std::string>(rng, {"readpixels", "pbo", "query", "reduce", "software"});
  if (r.method == Method::Hzb && r.reader == "query") r.reader = "readpixels";
  // The software reader rasterises inner coverage itself: single-sampled runs only.
  r.samples = r.reader == "software" ? 0u : pick(rng, {0u, 0u, 0u, 2u, 4u});
  return r;
}

struct Totals {
  std::uint64_t frames = 0, runs = 0, visible = 0, missed = 0, artifacts = 0, missed_artifacts = 0,
                drawn = 0, occluded = 0, tested = 0, errors = 0;
};

int usage(const char* why) {
  std::fprintf(stderr,
               "logrid_soak: %s\nusage: logrid_soak [--frames N] [--frames-per-run K] "
               "[--seed S] [--json FILE]\n",
               why);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t total_frames = 10000, per_run = 25, seed = 1;
  std::string json_path;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return usage(("missing value after " + a).c_str());
    const std::string v = argv[++i];
    char* end = nullptr;
    const unsigned long long n = std::strtoull(v.c_str(), &end, 10);
    const bool number = !v.empty() && *end == '\0';
    if (a == "--frames" && number && n > 0) {
      total_frames = n;
    } else if (a == "--frames-per-run" && number && n > 0) {
      per_run = n;
    } else if (a == "--seed" && number) {
      seed = n;
    } else if (a == "--json") {
      json_path = v;
    } else {
      return usage(("bad option " + a + " " + v).c_str());
    }
  }
  try {
    gl::ContextDesc context_desc;
    context_desc.debug = true;  // every GL error surfaces
    gl::Context context(context_desc);
    const std::string model_path = (std::filesystem::temp_directory_path() /
                                    ("logrid_soak_" + std::to_string(getpid()) + ".obj"))
                                       .string();
    std::mt19937_64 rng(seed);
    Totals t;
    std::map<std::string, std::uint64_t> frames_by_method, frames_by_reader;
    std::uint64_t start_hwm = 0, start_rss = 0, end_rss = 0;
    const auto start_time = std::chrono::steady_clock::now();

    // Warm-up: the largest configuration of each scene kind first, so that the start
    // peak already holds the largest scene, framebuffer and grid the run will see.
    std::vector<Run> warmup;
    for (const char* kind : {"forest", "city", "model"}) {
      Run r;
      r.scene = kind;
      r.scale = r.scene == "city" ? 0.016 : 0.1;
      r.width = 320;
      r.height = 240;
      r.tile = 3;
      r.samples = 4;
      r.method = Method::Hzb;
      warmup.push_back(r);
    }
    std::size_t run_index = 0;
    while (t.frames < total_frames) {
      const bool warming = run_index < warmup.size();
      const Run run = warming ? warmup[run_index] : randomRun(rng);
      ++run_index;
      Scene scene;
      if (run.scene == "city") {
        scene = makeCity({run.scale, run.seed});
      } else {
        scene = makeForest({run.scale, run.seed});
        if (run.scene == "model") {
          writeObj(scene, model_path);
          scene = loadSceneFile(model_path);  // with the loader's orbit around the model
        }
      }
      const bvh::BuildArgs args = defaultBuildArgs(scene);
      PreparedScene prepared = prepareScene(std::move(scene), args);
      auto renderer = std::make_unique<gl::MeshRenderer>(prepared.mesh);
      RunConfig config;
      config.method = MethodChoice{run.method};
      config.culler.tile_size = run.tile;
      config.reader = run.reader;
      config.view.width = run.width;
      config.view.height = run.height;
      config.view.near_plane = prepared.near_plane;
      config.view.far_plane = prepared.far_plane;
      config.view.depth = depthSetupFor(run.convention, run.format);
      config.view.samples = run.samples;
      config.frames = std::size_t(per_run);
      config.verify = true;
      try {
        FrameRunner runner(prepared, *renderer, config);
        for (std::size_t f = 0; f < config.frames; ++f) {
          const FrameRecord r = runner.renderFrame(f);
          ++t.frames;
          frames_by_method[toString(run.method)]++;
          frames_by_reader[run.reader]++;
          t.visible += std::uint64_t(std::max<std::int64_t>(r.visible, 0));
          t.artifacts += std::uint64_t(std::max<std::int64_t>(r.artifacts, 0));
          t.drawn += r.stats.objects_drawn;
          t.occluded += r.stats.boxes_occluded;
          t.tested += r.stats.boxes_tested;
          if (r.missed != 0 || r.missed_artifacts != 0 || r.visible < 0) {
            t.missed += std::uint64_t(std::max<std::int64_t>(r.missed, 0));
            t.missed_artifacts += std::uint64_t(std::max<std::int64_t>(r.missed_artifacts, 0));
            std::printf(
                "MISS run %zu frame %zu (%s): %lld missed, %lld missed artifacts, first "
                "object %u\n",
                run_index, f, run.describe().c_str(), (long long)r.missed,
                (long long)r.missed_artifacts, r.missed_ids.empty() ? 0u : r.missed_ids.front());
          }
        }
      } catch (const Error& e) {
        ++t.errors;
        std::printf("ERROR run %zu (%s): %s\n", run_index, run.describe().c_str(), e.what());
      }
      ++t.runs;
      renderer.reset();
      end_rss = statusKiB("VmRSS");
      if (run_index == warmup.size()) {
        start_hwm = statusKiB("VmHWM");
        start_rss = end_rss;
      }
      if (run_index % 20 == 0 || t.frames >= total_frames) {
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
        std::fprintf(stderr,
                     "soak: %llu/%llu frames, %llu runs, %llu missed, %llu errors, RSS %llu "
                     "KiB, peak %llu KiB, %.0f s\n",
                     (unsigned long long)t.frames, (unsigned long long)total_frames,
                     (unsigned long long)t.runs, (unsigned long long)t.missed,
                     (unsigned long long)t.errors, (unsigned long long)end_rss,
                     (unsigned long long)statusKiB("VmHWM"), s);
      }
    }
    std::error_code ec;
    std::filesystem::remove(model_path, ec);
    const std::uint64_t end_hwm = statusKiB("VmHWM");
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
    std::ostringstream summary;
    summary << "{\n  \"seed\": " << seed << ",\n  \"frames\": " << t.frames
            << ",\n  \"runs\": " << t.runs << ",\n  \"visible_objects\": " << t.visible
            << ",\n  \"missed_visible_objects\": " << t.missed
            << ",\n  \"depth_artifact_objects\": " << t.artifacts
            << ",\n  \"missed_depth_artifact_objects\": " << t.missed_artifacts
            << ",\n  \"errors\": " << t.errors << ",\n  \"objects_drawn\": " << t.drawn
            << ",\n  \"boxes_tested\": " << t.tested << ",\n  \"boxes_occluded\": " << t.occluded
            << ",\n  \"peak_rss_kib_after_warmup\": " << start_hwm
            << ",\n  \"peak_rss_kib_at_end\": " << end_hwm
            << ",\n  \"rss_kib_after_warmup\": " << start_rss
            << ",\n  \"rss_kib_at_end\": " << end_rss << ",\n  \"seconds\": " << seconds
            << ",\n  \"frames_by_method\": {";
    const char* sep = "";
    for (const auto& [k, v] : frames_by_method)
      summary << sep << "\"" << k << "\": " << v, sep = ", ";
    summary << "},\n  \"frames_by_reader\": {";
    sep = "";
    for (const auto& [k, v] : frames_by_reader)
      summary << sep << "\"" << k << "\": " << v, sep = ", ";
    summary << "}\n}\n";
    std::printf("%s", summary.str().c_str());
    if (!json_path.empty()) std::ofstream(json_path) << summary.str();
    return t.missed == 0 && t.missed_artifacts == 0 && t.errors == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "logrid_soak: %s\n", e.what());
    return 1;
  }
}
