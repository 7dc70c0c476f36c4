// The logrid command line: a repeated option is no usage error, the last one wins, on
// every option of every subcommand (samples/cli/commands.hpp, addCommands).
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/frame_runner.hpp"
#include "gl_test_context.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {
namespace {

namespace fs = std::filesystem;

// Runs `logrid ARGS...` in this process as main() does and returns the exit code of
// the subcommand (or -1 for a usage error).
int runLogrid(std::vector<std::string> args) {
  CLI::App app{"logrid"};
  addCommands(app);
  args.insert(args.begin(), "logrid");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  try {
    app.parse(int(argv.size()), argv.data());
  } catch (const CLI::RuntimeError& done) {
    return done.get_exit_code();
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "usage error: %s\n", e.what());
    return -1;
  }
  return 0;
}

nlohmann::json readJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "logrid_command_line_test";
  fs::create_directories(dir);
  return dir / name;
}

TEST(CommandLine, EveryOptionOfEverySubcommandTakesOneValueAndTheLastWins) {
  CLI::App app{"logrid"};
  addCommands(app);
  const std::vector<CLI::App*> commands = app.get_subcommands([](CLI::App*) { return true; });
  ASSERT_EQ(commands.size(), 6u);  // walk, bench, tune, calibrate, ddo, export
  std::size_t checked = 0;
  for (CLI::App* command : commands) {
    for (const CLI::Option* option : command->get_options()) {
      const std::string name = command->get_name() + " " + option->get_name();
      EXPECT_EQ(option->get_multi_option_policy(), CLI::MultiOptionPolicy::TakeLast) << name;
      // A list option would gather the values of every repetition instead.
      EXPECT_LE(option->get_expected_max(), 1) << name << " takes several values";
      ++checked;
    }
  }
  EXPECT_GT(checked, 60u);  // walk, bench and tune have some 25 options each, the others fewer
}

TEST(CommandLine, WalkWithRepeatedFramesWalksTheLastCount) {
  LOGRID_REQUIRE_GL();
  const fs::path json = scratch("walk.json");
  fs::remove(json);
  ASSERT_EQ(runLogrid({"walk", "--scene", "forest", "--scale", "0.02", "--frames", "8", "--size",
                       "64x48", "--size", "48x32", "--json", json.string(), "--frames", "2"}),
            0);
  const nlohmann::json report = readJson(json);
  EXPECT_EQ(report["frames"], 2);
  EXPECT_EQ(report["per_frame"].size(), 2u);
  EXPECT_EQ(report["width"], 48);
  EXPECT_EQ(report["height"], 32);
}

TEST(CommandLine, WalkReportsAnApproximateSettingsMissesWithoutFailing) {
  LOGRID_REQUIRE_GL();
  // Misses are what an approximate setting pays for its speed: reported, exit 0. The same
  // walk exact draws every visible object; a budget counts as approximate.
  const fs::path json = scratch("walk_approximate.json");
  const std::vector<std::string> walk = {
      "walk",   "--scene", "forest",   "--scale",  "0.3",       "--frames", "3",
      "--size", "160x120", "--verify", "--method", "log-state", "--json",   json.string()};
  std::vector<std::string> approximate = walk;
  approximate.insert(approximate.end(), {"--full-fraction", "0.9"});
  ASSERT_EQ(runLogrid(approximate), 0);
  nlohmann::json report = readJson(json);
  EXPECT_FALSE(report["conservative"].get<bool>());
  EXPECT_GT(report["missed_visible_objects"].get<std::int64_t>(), 0);

  ASSERT_EQ(runLogrid(walk), 0);
  report = readJson(json);
  EXPECT_TRUE(report["conservative"].get<bool>());
  EXPECT_EQ(report["missed_visible_objects"].get<std::int64_t>(), 0);

  std::vector<std::string> budget = walk;
  budget.insert(budget.end(), {"--budget-ms", "1000"});
  ASSERT_EQ(runLogrid(budget), 0);
  report = readJson(json);
  EXPECT_FALSE(report["conservative"].get<bool>());
  EXPECT_EQ(report["budget_ms"].get<double>(), 1000.0);
}

TEST(CommandLine, TuneWithRepeatedTilesSweepsTheLastList) {
  LOGRID_REQUIRE_GL();
  const fs::path json = scratch("tune.json");
  fs::remove(json);
  ASSERT_EQ(
      runLogrid({"tune", "--scene", "forest", "--scale", "0.02", "--size", "64x48", "--frames", "1",
                 "--repeat", "1", "--tiles", "8,16", "--json", json.string(), "--tiles", "32"}),
      0);
  const nlohmann::json report = readJson(json);
  ASSERT_EQ(report["sizes"].size(), 1u);
  EXPECT_EQ(report["recommended_tile"], 32);
}

TEST(CommandLine, ABadTileListIsAUsageErrorNamingTheItem) {
  testing::internal::CaptureStderr();
  EXPECT_EQ(runLogrid({"tune", "--scene", "forest", "--tiles", "8,x"}), -1);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("--tiles: in '8,x', 'x' is not a number in range [1, 32768]"),
            std::string::npos)
      << err;
}

// tune --auto sweeps in stages, says what the scene needed, and writes a configuration
// that keeps only those parts and that walk then runs as written (method, lookahead,
// coherence, tile, reader).
TEST(CommandLine, ClustersBuiltByEitherMethodMissNothing) {
  LOGRID_REQUIRE_GL();
  // --cluster-method picks meshoptimizer's builder; the clusters differ, the walk stays
  // exact. An unknown builder is refused naming the choices.
  std::vector<std::uint64_t> clusters;
  for (const char* method : {"grow", "scan"}) {
    const fs::path json = scratch(std::string("walk_cluster_") + method + ".json");
    ASSERT_EQ(runLogrid({"walk", "--scene", "forest", "--scale", "0.05", "--frames", "3", "--size",
                         "160x120", "--cluster", "64", "--cluster-method", method, "--verify",
                         "--json", json.string()}),
              0)
        << method;
    const nlohmann::json report = readJson(json);
    EXPECT_EQ(report["missed_visible_objects"].get<std::int64_t>(), 0) << method;
    clusters.push_back(report["clusters"].get<std::uint64_t>());
    EXPECT_GT(clusters.back(), report["source_objects"].get<std::uint64_t>()) << method;
  }
  // (main() prints the error and exits 2, as for any bad input.)
  try {
    runLogrid({"walk", "--scene", "forest", "--scale", "0.02", "--frames", "1", "--size", "64x48",
               "--cluster", "64", "--cluster-method", "greedy"});
    ADD_FAILURE() << "an unknown cluster method was taken";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    EXPECT_STREQ(e.what(), "cluster method 'greedy' is unknown; use grow or scan");
  }
}

TEST(CommandLine, TuneAutoWritesAConfigurationThatWalkRuns) {
  LOGRID_REQUIRE_GL();
  const fs::path config = scratch("auto_config.json");
  const fs::path tune = scratch("auto_tune.json");
  const fs::path walk = scratch("auto_walk.json");
  for (const fs::path& p : {config, tune, walk}) fs::remove(p);
  ASSERT_EQ(runLogrid({"tune", "--auto", "--scene", "forest", "--scale", "0.02", "--size", "64x48",
                       "--frames", "2", "--repeat", "1", "--json", tune.string(), "--write-config",
                       config.string()}),
            0);
  const nlohmann::json report = readJson(tune);
  ASSERT_GE(report["stages"].size(), 2u);  // the methods, then at least the granularity
  EXPECT_GE(report["stages"][0]["candidates"].size(), 10u);
  ASSERT_EQ(report["needed"].size(), 3u);
  const nlohmann::json file = readJson(config);
  EXPECT_EQ(file["format"], "logrid-config");
  EXPECT_TRUE(file["scene"].contains("leaf"));
  const nlohmann::json& c = file["culler"];
  // It keeps no part its own report calls not needed.
  const nlohmann::json& needed = report["needed"];
  const auto notNeeded = [&](std::size_t part) { return needed[part]["needed"] == false; };
  if (notNeeded(0)) {
    EXPECT_EQ(c["method"], "vfc");
  }
  if (c["method"] != "vfc") {
    if (notNeeded(1)) {
      EXPECT_EQ(c["lookahead"], 1);
    }
    if (notNeeded(2)) {
      EXPECT_EQ(c["temporal_coherence"], false);
    }
  }
  ASSERT_EQ(runLogrid({"walk", "--scene", "forest", "--scale", "0.02", "--size", "64x48",
                       "--frames", "2", "--config", config.string(), "--json", walk.string()}),
            0);
  const nlohmann::json ran = readJson(walk);
  EXPECT_EQ(ran["tile"], c["tile_size"]);
  EXPECT_EQ(ran["reader"], file["source"]);
  EXPECT_EQ(ran["method"].get<std::string>().substr(0, c["method"].get<std::string>().size()),
            c["method"]);
  if (ran["method"] != "vfc" && ran["method"] != "auto") {
    EXPECT_EQ(ran["lookahead"], c["lookahead"]);
    EXPECT_EQ(ran["temporal_coherence"], c["temporal_coherence"]);
  }
}

TEST(CommandLine, AConfigurationCannotBeGivenBesideTheOptionsItSets) {
  const fs::path config = scratch("beside.json");
  std::ofstream(config) << "{\"format\": \"logrid-config\", \"version\": 1, \"culler\": {}}";
  for (const char* option : {"--method", "--tile", "--reader", "--lookahead"}) {
    const std::string value = std::string(option) == "--method"   ? "vfc"
                              : std::string(option) == "--reader" ? "pbo"
                                                                  : "8";
    EXPECT_EQ(runLogrid({"walk", "--scene", "forest", option, value, "--config", config.string()}),
              -1)
        << option;
  }
  EXPECT_EQ(runLogrid({"walk", "--scene", "forest", "--coherence", "--config", config.string()}),
            -1);
}

TEST(CommandLine, ABadConfigurationIsRefusedNamingTheFileAndTheKey) {
  const fs::path config = scratch("bad_config.json");
  std::ofstream(config)
      << "{\"format\": \"logrid-config\", \"version\": 1, \"culler\": {\"tile_size\": -4}}";
  try {
    runLogrid({"walk", "--scene", "forest", "--config", config.string()});
    ADD_FAILURE() << "a bad configuration was run";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::BadInput);
    const std::string what = e.what();
    EXPECT_NE(what.find(config.string()), std::string::npos) << what;
    EXPECT_NE(what.find("tile_size"), std::string::npos) << what;
  }
  std::ofstream(config) << "{\"format\": \"logrid-config\", \"version\": 1, \"culler\": {},"
                           " \"scene\": {\"leaf\": -1}}";
  EXPECT_THROW(runLogrid({"walk", "--scene", "forest", "--config", config.string()}), Error);
}

// Method names come from the method table; a setting suffix is taken only where the
// method takes that setting (MethodTakes), and a refusal says what the method takes.
TEST(MethodChoices, EveryMethodOfTheTableAndItsSettings) {
  for (const MethodInfo& m : methodTable()) {
    EXPECT_NE(methodChoiceHelp().find(m.name), std::string::npos) << m.name;
    const auto plain = parseMethodChoice(m.name);
    ASSERT_TRUE(plain) << m.name;
    EXPECT_EQ(plain->method, m.method);
    EXPECT_EQ(plain->name(), m.name);
    std::string problem;
    const auto with_k = parseMethodChoice(std::string(m.name) + ":16", &problem);
    EXPECT_EQ(with_k.has_value(), m.takes.lookahead) << m.name << ": " << problem;
    const auto with_tc = parseMethodChoice(std::string(m.name) + ":tc", &problem);
    EXPECT_EQ(with_tc.has_value(), m.takes.temporal_coherence) << m.name << ": " << problem;
    const auto with_schedule = parseMethodChoice(std::string(m.name) + ":chc", &problem);
    EXPECT_EQ(with_schedule.has_value(), m.takes.query_schedule) << m.name << ": " << problem;
  }
  const auto both = parseMethodChoice("ddo+log:16:tc");
  ASSERT_TRUE(both);
  EXPECT_EQ(both->method, Method::DdoLog);
  EXPECT_EQ(both->lookahead, 16u);
  EXPECT_TRUE(both->coherence);
  EXPECT_EQ(both->name(), "ddo+log:16:tc");
  EXPECT_TRUE(parseMethodChoice("oracle")->oracle());

  std::string problem;
  EXPECT_FALSE(parseMethodChoice("vfc:16", &problem));
  EXPECT_NE(problem.find("it takes none"), std::string::npos) << problem;
  EXPECT_FALSE(parseMethodChoice("log-state:16:8", &problem));
  EXPECT_NE(problem.find("'8'"), std::string::npos) << problem;
  EXPECT_NE(problem.find(":tc"), std::string::npos) << problem;
  EXPECT_FALSE(parseMethodChoice("log-state:0", &problem));
  EXPECT_NE(problem.find("lookahead 0 is invalid"), std::string::npos) << problem;
  EXPECT_FALSE(parseMethodChoice("oracle:tc", &problem));
  EXPECT_FALSE(parseMethodChoice("fast", &problem));
  EXPECT_NE(problem.find("'fast' is unknown"), std::string::npos) << problem;
}

}  // namespace
}  // namespace logrid::samples
