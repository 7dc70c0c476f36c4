// logrid tune: placeholder until the tuning tool lands.
#include "cli/commands.hpp"

namespace logrid::samples {
void addTuneCommand(CLI::App&) {}
}  // namespace logrid::samples
