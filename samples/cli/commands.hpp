// The logrid subcommands. Each returns the process exit code: 0 success, 1 runtime
// failure (including a conservative method missing a visible object under --verify),
// 2 bad usage or bad input (logrid::Error InvalidArgument/BadInput, thrown upwards).
#pragma once

#include <CLI/CLI.hpp>

namespace logrid::samples {

void addWalkCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addTuneCommand(CLI::App& app);
void addDdoCommand(CLI::App& app);
void addExportCommand(CLI::App& app);

}  // namespace logrid::samples
