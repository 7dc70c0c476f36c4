// The soak run (scripts/soak.sh; not part of CI): many thousands of frames, each checked
// against the object-ID oracle, over random scenes and settings in one process, to find
// rare misses and memory that grows.
//
// Each run picks, from a seeded generator: a scene (the forest or the city at a small
// scale with a random seed, or a model file: a small forest written as OBJ and read back
// through the assimp loader, walked on the loader's orbit), moving objects or none (with
// each motion hierarchy, and frames either spread over the path or close together), a
// size, a tile size, a depth format and convention, a sample count, a method of the
// library's table (logrid::methodTable(): the grids, the baselines, the hardware-query
// schedules, DDO with its octree built for the run) with the settings it takes (lookahead
// K, temporal coherence, log+hwq's query schedule), and a reader (every one, cpu with a
// random resolution, occluder choice and worker count). It walks `--frames-per-run`
// frames. Every visible object must be drawn (misses and missed depth-extrapolation
// artifacts both fail the run). Scenes are generated, uploaded and released per run.
//
// Memory: after a warm-up that visits the largest configuration of each scene kind, the
// resident set's high-water mark (VmHWM) is recorded as the start figure; in the middle
// (the first run that ends past half the frames) and at the end it is recorded again,
// with the resident set (VmRSS) and the C heap in use at each. Flat memory means the
// middle and end peaks equal the start peak up to allocator noise; a run that raises the
// peak after the warm-up is named on stderr, and --memory-trace FILE writes every run's
// figures (one line a run: RSS, peak, heap in use and held, threads, its setting).
//
// Usage: logrid_soak [--frames N] [--frames-per-run K] [--seed S] [--json FILE]
//                    [--memory-trace FILE]
// Exit status 0 when no visible object was missed, 1 otherwise, 2 for bad usage.
#include <malloc.h>
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
#include "scene/ddo_scene.hpp"
#include "scene/generators.hpp"
#include "scene/loader.hpp"
#include "scene/movers.hpp"
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

// The C heap, in KiB: what is allocated now (in use, small blocks and mmapped ones) and
// what the allocator holds from the system for it (its arenas' and mmapped blocks'
// bytes). Llvmpipe's allocations are on it too. A leak shows as "in use" growing from run
// to run; a peak first reached after the warm-up with "in use" back to its level after
// the run is a larger configuration visited for the first time.
struct Heap {
  std::uint64_t in_use_kib = 0, held_kib = 0;
};
Heap heap() {
  const struct mallinfo2 m = mallinfo2();
  return {(m.uordblks + m.hblkhd) / 1024, (m.arena + m.hblkhd) / 1024};
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
  MethodChoice method{Method::LogState};  // with its settings
  std::string reader = "readpixels";
  CpuReaderOptions cpu;
  std::uint32_t movers = 0;
  std::string hierarchy = "auto";
  double time_step = 0;
  bool colliding = false;

  std::string describe() const {
    std::ostringstream out;
    out << scene << " scale " << scale << " seed " << seed << ", " << width << "x" << height
        << " tile " << tile << ", " << toString(format) << " " << toString(convention) << ", "
        << method.name() << " / " << reader << ", samples " << samples;
    if (reader == "cpu") {
      out << " (cpu " << cpu::toString(cpu.resolution) << " " << toString(cpu.occluders) << " "
          << cpu.threads << " threads)";
    }
    if (movers) out << ", " << movers << " movers on " << hierarchy << " step " << time_step;
    if (colliding) out << ", colliding";
    return out.str();
  }
};

template <typename T>
T pick(std::mt19937_64& rng, std::initializer_list<T> values) {
  return *(values.begin() + std::uniform_int_distribution<std::size_t>(0, values.size() - 1)(rng));
}

template <typename T>
const T& pickFrom(std::mt19937_64& rng, const std::vector<T>& values) {
  return values[std::uniform_int_distribution<std::size_t>(0, values.size() - 1)(rng)];
}

// A method of the table with random settings among those it takes.
MethodChoice randomMethod(std::mt19937_64& rng) {
  const MethodInfo& info = pickFrom(rng, methodTable());
  MethodChoice c{info.method};
  if (info.takes.lookahead) {
    c.lookahead = pick(rng, {1u, 1u, 4u, 16u, kUnlimitedLookahead});
  }
  if (info.takes.temporal_coherence) c.coherence = rng() % 2 == 0;
  if (info.takes.query_schedule) {
    c.schedule = pick(
        rng, {QuerySchedule::Hwq, QuerySchedule::Chc, QuerySchedule::Stat, QuerySchedule::Nohc});
  }
  return c;
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
  r.method = randomMethod(rng);
  const MethodInfo& info = methodInfo(*r.method.method);
  std::vector<std::string> readers;
  for (const ReaderInfo& reader : readerTable()) {
    if (info.needs.depth_values && !reader.reads_depth) continue;  // refused up front
    readers.push_back(reader.name);
  }
  r.reader = pickFrom(rng, readers);
  r.cpu.resolution =
      pick(rng, {cpu::Resolution::Full, cpu::Resolution::Half, cpu::Resolution::Quarter});
  r.cpu.occluders = pick(rng, {OccluderChoice::Mesh, OccluderChoice::Model});
  r.cpu.threads = pick(rng, {0u, 0u, 1u, 3u});
  // The software reader rasterises inner coverage itself: single-sampled runs only.
  r.samples = r.reader == "software" ? 0u : pick(rng, {0u, 0u, 0u, 2u, 4u});
  if (rng() % 3 == 0) {
    r.movers = pick(rng, {5u, 20u, 60u});
    r.hierarchy = pickFrom(rng, bvh::motionTable()).name;
    r.time_step = pick(rng, {0.0, 0.0, 0.5, 3.0});
  }
  r.colliding = info.takes.lookahead && rng() % 4 == 0;
  return r;
}

struct Totals {
  std::uint64_t frames = 0, runs = 0, visible = 0, missed = 0, artifacts = 0, missed_artifacts = 0,
                drawn = 0, occluded = 0, tested = 0, errors = 0;
};

int usage(const char* why) {
  std::fprintf(stderr,
               "logrid_soak: %s\nusage: logrid_soak [--frames N] [--frames-per-run K] "
               "[--seed S] [--json FILE] [--memory-trace FILE]\n",
               why);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t total_frames = 10000, per_run = 25, seed = 1;
  std::string json_path, trace_path;
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
    } else if (a == "--memory-trace") {
      trace_path = v;
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
    std::map<std::string, std::uint64_t> frames_by_method, frames_by_reader, frames_by_setting;
    std::uint64_t start_hwm = 0, start_rss = 0, middle_hwm = 0, middle_rss = 0, end_rss = 0;
    std::uint64_t last_hwm = 0, start_heap = 0, middle_heap = 0;
    std::ofstream trace;
    if (!trace_path.empty()) {
      trace.open(trace_path);
      trace << "run\tframes\trss_kib\tpeak_kib\theap_in_use_kib\theap_held_kib\tthreads\tsetting\n";
    }
    const auto start_time = std::chrono::steady_clock::now();

    // Warm-up: each scene kind at its largest scale, three times, so that the start peak
    // already holds the largest configuration the random runs can reach: with the largest
    // framebuffer and grid (320x240, 4 samples, tile 3); with the cpu reader at full
    // resolution without workers (one thread sets up the whole frame's occluder triangles
    // before binning them) and 60 movers rebuilt each frame; and with DDO's octree and its
    // preprocessing at 64 regions. With the first alone, a later city run with the cpu
    // reader raised the peak by about 100 MiB: a configuration visited for the first time,
    // its memory freed after the run (docs/DESIGN.md, "The soak run").
    std::vector<Run> warmup;
    for (const char* kind : {"forest", "city", "model"}) {
      Run r;
      r.scene = kind;
      r.scale = r.scene == "city" ? 0.016 : 0.1;
      r.width = 320;
      r.height = 240;
      r.tile = 3;
      r.samples = 4;
      r.method = MethodChoice{Method::Hzb};
      warmup.push_back(r);
      Run cpu = r;
      cpu.reader = "cpu";
      cpu.cpu.resolution = cpu::Resolution::Full;
      cpu.cpu.occluders = OccluderChoice::Mesh;
      cpu.cpu.threads = 0;
      cpu.movers = 60;
      cpu.hierarchy = "rebuild";
      warmup.push_back(cpu);
      Run ddo = r;
      ddo.method = MethodChoice{Method::Ddo};
      warmup.push_back(ddo);
    }
    std::size_t run_index = 0;
    while (t.frames < total_frames) {
      const bool warming = run_index < warmup.size();
      const Run run = warming ? warmup[run_index] : randomRun(rng);
      ++run_index;
      // Everything of a run (scene, renderer, runner, frames) inside one try: an error
      // ends that run only, and the GL errors it left pending are drained before the next.
      std::unique_ptr<gl::MeshRenderer> renderer;
      try {
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
        addMovers(scene, run.movers, run.seed);
        const bvh::BuildArgs args = defaultBuildArgs(scene);
        PreparedScene prepared = prepareScene(std::move(scene), args);
        if (methodInfo(*run.method.method).needs.occluders) {
          DdoOptions ddo;
          ddo.regions = warming ? 64u : pick(rng, {32u, 64u});
          ddo.threads = 2;
          ddo.progress = false;
          prepared.ddo = prepareDdo(prepared, ddo).octree;
        }
        renderer = std::make_unique<gl::MeshRenderer>(prepared.mesh);
        RunConfig config;
        config.method = run.method;
        if (run.method.lookahead) config.culler.lookahead = *run.method.lookahead;
        config.culler.temporal_coherence = run.method.coherence;
        if (run.method.schedule) config.culler.queries.schedule = *run.method.schedule;
        config.culler.detect_colliding = run.colliding;
        config.culler.tile_size = run.tile;
        config.reader = run.reader;
        config.cpu = run.cpu;
        config.hierarchy = run.movers ? run.hierarchy : "auto";
        config.time_step = run.time_step;
        config.view.width = run.width;
        config.view.height = run.height;
        config.view.near_plane = prepared.near_plane;
        config.view.far_plane = prepared.far_plane;
        config.view.depth = depthSetupFor(run.convention, run.format);
        config.view.samples = run.samples;
        config.frames = std::size_t(per_run);
        config.verify = true;
        FrameRunner runner(prepared, *renderer, config);
        for (std::size_t f = 0; f < config.frames; ++f) {
          const FrameRecord r = runner.renderFrame(f);
          ++t.frames;
          frames_by_method[toString(*run.method.method)]++;
          frames_by_reader[run.reader]++;
          if (run.method.lookahead && *run.method.lookahead > 1) frames_by_setting["lookahead"]++;
          if (run.method.coherence) frames_by_setting["coherence"]++;
          if (run.method.schedule) frames_by_setting[toString(*run.method.schedule)]++;
          if (run.movers) frames_by_setting["movers/" + run.hierarchy]++;
          if (run.colliding) frames_by_setting["colliding"]++;
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
        try {
          gl::checkGlErrors("soak: after the failed run");
        } catch (const Error&) {
          // reported above; the next run starts without them
        }
      }
      ++t.runs;
      renderer.reset();
      end_rss = statusKiB("VmRSS");
      const std::uint64_t hwm = statusKiB("VmHWM");
      const Heap h = heap();
      if (trace) {
        trace << run_index << "\t" << t.frames << "\t" << end_rss << "\t" << hwm << "\t"
              << h.in_use_kib << "\t" << h.held_kib << "\t" << statusKiB("Threads") << "\t"
              << run.describe() << "\n"
              << std::flush;
      }
      if (run_index > warmup.size() && hwm > last_hwm) {
        std::fprintf(stderr, "soak: peak %llu KiB (+%llu) in run %zu (%s)\n",
                     (unsigned long long)hwm, (unsigned long long)(hwm - last_hwm), run_index,
                     run.describe().c_str());
      }
      last_hwm = hwm;
      if (run_index == warmup.size()) {
        start_hwm = statusKiB("VmHWM");
        start_rss = end_rss;
        start_heap = h.in_use_kib;
        std::fprintf(stderr, "soak: after warm-up RSS %llu KiB, peak %llu KiB\n",
                     (unsigned long long)start_rss, (unsigned long long)start_hwm);
      }
      if (middle_hwm == 0 && 2 * t.frames >= total_frames && run_index > warmup.size()) {
        middle_hwm = statusKiB("VmHWM");
        middle_rss = end_rss;
        middle_heap = h.in_use_kib;
        std::fprintf(stderr, "soak: middle (%llu frames) RSS %llu KiB, peak %llu KiB\n",
                     (unsigned long long)t.frames, (unsigned long long)middle_rss,
                     (unsigned long long)middle_hwm);
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
            << ",\n  \"peak_rss_kib_middle\": " << middle_hwm
            << ",\n  \"peak_rss_kib_at_end\": " << end_hwm
            << ",\n  \"rss_kib_after_warmup\": " << start_rss
            << ",\n  \"rss_kib_middle\": " << middle_rss << ",\n  \"rss_kib_at_end\": " << end_rss
            << ",\n  \"heap_in_use_kib_after_warmup\": " << start_heap
            << ",\n  \"heap_in_use_kib_middle\": " << middle_heap
            << ",\n  \"heap_in_use_kib_at_end\": " << heap().in_use_kib
            << ",\n  \"seconds\": " << seconds << ",\n  \"frames_by_method\": {";
    const char* sep = "";
    for (const auto& [k, v] : frames_by_method)
      summary << sep << "\"" << k << "\": " << v, sep = ", ";
    summary << "},\n  \"frames_by_reader\": {";
    sep = "";
    for (const auto& [k, v] : frames_by_reader)
      summary << sep << "\"" << k << "\": " << v, sep = ", ";
    summary << "},\n  \"frames_by_setting\": {";
    sep = "";
    for (const auto& [k, v] : frames_by_setting)
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
