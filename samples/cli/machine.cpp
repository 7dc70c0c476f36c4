#include "cli/machine.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include "logrid/error.hpp"

namespace logrid::samples {

gl::ContextDesc contextDesc(const WalkOptions& o) {
  gl::ContextDesc d;
  const auto platform = gl::parsePlatform(o.platform);
  if (!platform) {
    throw Error(ErrorCode::InvalidArgument,
                "platform '" + o.platform + "' is unknown; use auto, surfaceless or device");
  }
  d.platform = *platform;
  // Mesa reads LP_NUM_THREADS when the driver starts, i.e. when the context is made.
  if (o.lp_threads >= 0) setenv("LP_NUM_THREADS", std::to_string(o.lp_threads).c_str(), 1);
  return d;
}

nlohmann::json machineInfo(const gl::Context& context) {
  std::string cpu;
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);) {
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
  const char* lp = std::getenv("LP_NUM_THREADS");
  const gl::ContextInfo& gl = context.info();
  return {{"gl_renderer", gl.renderer},
          {"gl_version", gl.version},
          {"gl_vendor", gl.vendor},
          {"egl_platform", gl::toString(gl.platform)},
          {"software_rasterizer", gl.software},
          {"cores", std::thread::hardware_concurrency()},
          {"cpu", cpu},
          {"lp_num_threads", lp ? lp : ""}};
}

std::string machineLine(const nlohmann::json& m) {
  std::ostringstream out;
  out << m["gl_renderer"].get<std::string>() << " (" << m["gl_version"].get<std::string>() << "), "
      << m["cores"].get<unsigned>() << " cores, " << m["cpu"].get<std::string>();
  return out.str();
}

std::uint64_t peakRssBytes() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stoull(line.substr(6)) * 1024;
  }
  return 0;
}

}  // namespace logrid::samples
