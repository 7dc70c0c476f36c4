// logrid bench: placeholder until the benchmark lands.
#include "cli/commands.hpp"

namespace logrid::samples {
void addBenchCommand(CLI::App&) {}
}  // namespace logrid::samples
