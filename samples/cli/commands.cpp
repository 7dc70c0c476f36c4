#include "cli/commands.hpp"

namespace logrid::samples {

void addCommands(CLI::App& app) {
  // The one place that sets the policy: subcommands copy their parent's option defaults
  // when they are created, and every option copies its app's defaults when it is added
  // (flags are TakeLast in CLI11 anyway).
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  addWalkCommand(app);
  addBenchCommand(app);
  addTuneCommand(app);
  addCalibrateCommand(app);
  addDdoCommand(app);
  addExportCommand(app);
}

}  // namespace logrid::samples
