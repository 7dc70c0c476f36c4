// logrid: occlusion-culling walkthroughs, benchmarks, tuning and the interactive viewer.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "cli/commands.hpp"
#include "cli/report.hpp"
#include "logrid/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"logrid: conservative occlusion culling with a lazy occlusion grid"};
  logrid::samples::setCommandLine(argc, argv);
  app.require_subcommand(1);
  logrid::samples::addCommands(app);
  logrid::samples::addViewCommand(app);  // after addCommands: takes its option policy
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& done) {
    return done.get_exit_code();  // a command finished and returned its exit code
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const logrid::Error& e) {
    std::fprintf(stderr, "logrid: %s\n", e.what());
    const bool input =
        e.code() == logrid::ErrorCode::InvalidArgument || e.code() == logrid::ErrorCode::BadInput;
    return input ? 2 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "logrid: %s\n", e.what());
    return 1;
  }
  return 0;
}
