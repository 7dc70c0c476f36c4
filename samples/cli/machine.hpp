// The machine a command runs on: the GL context the options ask for, the renderer, cores
// and CPU that reports name, and the process's peak memory.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

#include "cli/options.hpp"
#include "logrid/gl/context.hpp"

namespace logrid::samples {

// The context --platform and --lp-threads ask for (sets LP_NUM_THREADS for llvmpipe).
gl::ContextDesc contextDesc(const WalkOptions& o);

// GL renderer, cores, CPU model, LP_NUM_THREADS.
nlohmann::json machineInfo(const gl::Context& context);
std::string machineLine(const nlohmann::json& machine);

// Reads the peak resident set size of this process (bytes), 0 if unknown.
std::uint64_t peakRssBytes();

}  // namespace logrid::samples
