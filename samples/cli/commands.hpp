// The logrid subcommands. Each returns the process exit code: 0 success, 1 runtime
// failure (including a conservative method missing a visible object under --verify),
// 2 bad usage or bad input (logrid::Error InvalidArgument/BadInput, thrown upwards).
#pragma once

#include <CLI/CLI.hpp>

namespace logrid::samples {

// Adds walk, bench, tune, calibrate, ddo and export to `app`. Every option of every
// subcommand takes one value, and a repeated option is no usage error: the last one wins,
// as in common command-line tools (`logrid walk --frames 8 ... --frames 2` walks 2
// frames), so that a script can pass defaults and then its caller's arguments.
void addCommands(CLI::App& app);

void addWalkCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addTuneCommand(CLI::App& app);
void addCalibrateCommand(CLI::App& app);
void addDdoCommand(CLI::App& app);
void addExportCommand(CLI::App& app);
// samples/viewer/view_command.cpp, or cli/view_unavailable.cpp in a build without GLFW
// and Dear ImGui. Not in addCommands (logrid_app cannot depend on the viewer, which
// depends on it): main() adds it after addCommands, so it takes the same option policy.
void addViewCommand(CLI::App& app);

}  // namespace logrid::samples
