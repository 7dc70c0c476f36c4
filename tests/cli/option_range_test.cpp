// Every number a user types is checked (samples/cli/option_checks.hpp): the test walks
// every option of every subcommand of the command line main() builds, so that an option
// added later cannot escape it. A numeric option must state its range in its help text
// ("range [1, 10000000]") and refuse, as a usage error that names the option, the value
// and the range, what lies outside it: NaN, infinities, values below and above the
// range (negative, zero where meaningless), fractions for whole numbers, overflow, text.
// Text options that hold numbers (sizes, lookaheads, lists of counts) are fed the same;
// every other text option must be one this test knows to hold no number.
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/option_checks.hpp"
#include "logrid/cpu/occlusion_buffer.hpp"
#include "logrid/culler.hpp"
#include "logrid/ddo/build.hpp"
#include "logrid/error.hpp"
#include "logrid/grid.hpp"
#include "logrid/query_schedule.hpp"
#include "process.hpp"
#include "scene/generators.hpp"

namespace logrid::samples {
namespace {

// Text options that hold no number: names, choices and paths.
const std::set<std::string> kTextOptions = {
    "--costs",          "--config",       "--write-config",
    "--scene",          "--path",         "--tree-parts",
    "--cluster-method", "--animate",      "--platform",
    "--ddo-file",       "--reader",       "--hierarchy",
    "--cpu-resolution", "--cpu-buffer",   "--occluders",
    "--cpu-isa",        "--depth-format", "--depth-convention",
    "--query-schedule", "--query-shape",  "--method",
    "--json",           "--images",       "--markdown",
    "--plots",          "--scenes",       "--methods",
    "--readers",        "--hierarchies",  "--motion-method",
    "--plot",           "--obj",          "--path-json",
    "--script",         "--out"};

constexpr int kParsed = 99;  // what a subcommand's callback returns here instead of running

// The command line as main() defines it. No subcommand runs: once a command line is
// parsed and checked, the app's own callback (which CLI11 runs before the subcommand's)
// returns kParsed.
std::unique_ptr<CLI::App> commandLine() {
  auto app = std::make_unique<CLI::App>("logrid");
  addCommands(*app);
  addViewCommand(*app);
  app->parse_complete_callback([] { throw CLI::RuntimeError(kParsed); });
  return app;
}

struct Outcome {
  bool parsed = false;  // accepted: the subcommand would have run
  std::string usage_error;
};

// `logrid COMMAND REQUIRED... --OPTION=VALUE` (= keeps "-1" and "-inf" a value).
Outcome parse(const std::string& command, const std::string& option, const std::string& value) {
  auto app = commandLine();
  std::vector<std::string> args = {"logrid", command};
  for (const CLI::Option* o : app->get_subcommand(command)->get_options()) {
    if (o->get_required()) args.insert(args.end(), {o->get_name(), "forest"});
  }
  args.push_back(option + "=" + value);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  Outcome out;
  try {
    app->parse(int(argv.size()), argv.data());
  } catch (const CLI::RuntimeError& e) {
    out.parsed = e.get_exit_code() == kParsed;
  } catch (const CLI::ParseError& e) {
    out.usage_error = e.what();
  }
  return out;
}

// The interval of a help text's "range [lo, hi]", "(lo, hi)", ... or set "{a, b}".
struct StatedRange {
  char open = 0, close = 0;
  std::vector<std::string> values;  // the interval's two ends, or the set's members
  std::string text;
};

StatedRange statedRange(const std::string& help, const std::string& prefix = "range ") {
  StatedRange r;
  const std::size_t at = help.rfind(prefix);
  if (at == std::string::npos) return r;
  const std::size_t start = at + prefix.size();
  const std::size_t end = help.find_first_of(")]}", start);
  if (end == std::string::npos) return r;
  r.text = help.substr(start, end + 1 - start);
  r.open = r.text.front();
  r.close = r.text.back();
  std::string inner = r.text.substr(1, r.text.size() - 2);
  for (std::size_t comma; (comma = inner.find(", ")) != std::string::npos;) {
    r.values.push_back(inner.substr(0, comma));
    inner = inner.substr(comma + 2);
  }
  r.values.push_back(inner);
  return r;
}

// A whole number written out, one above or below (any size logrid's options take).
std::string wholeStep(const std::string& n, int step) {
  __int128 v = 0;
  for (char c : n) {
    if (c >= '0' && c <= '9') v = v * 10 + (c - '0');
  }
  if (n[0] == '-') v = -v;
  v += step;
  const bool negative = v < 0;
  if (negative) v = -v;
  std::string out;
  do {
    out.insert(out.begin(), char('0' + int(v % 10)));
    v /= 10;
  } while (v > 0);
  return negative ? "-" + out : out;
}

bool wholeType(const CLI::Option& o) {
  const std::string type = o.get_type_name();
  return type == "INT" || type == "UINT";
}

// Values outside a stated range, for a whole-number or a real option.
std::vector<std::string> outside(const StatedRange& r, bool whole) {
  std::vector<std::string> out = {"nan",    "NaN", "-nan", "-inf", "1e400",
                                  "-1e400", "",    "abc",  "5x",   "1,5"};
  if (!(r.open != '{' && r.values.back() == "inf" && r.close == ']')) {
    out.insert(out.end(), {"inf", "infinity"});  // unless infinity is in the range
  }
  if (whole) {
    out.insert(out.end(), {"1.5", "1e3", "99999999999999999999999", "-99999999999999999999999"});
  }
  if (r.open == '{') {
    for (const std::string& v : r.values) {
      out.push_back(wholeStep(v, 1));
      out.push_back(wholeStep(v, -1));
    }
    return out;
  }
  const std::string& lo = r.values.front();
  const std::string& hi = r.values.back();
  if (r.open == '(') out.push_back(lo);
  if (r.open == '[') out.push_back(whole ? wholeStep(lo, -1) : std::to_string(std::stod(lo) - 1));
  if (hi != "inf" && r.close == ')') out.push_back(hi);
  if (hi != "inf" && r.close == ']') {
    out.push_back(whole ? wholeStep(hi, 1) : std::to_string(std::stod(hi) * 2 + 1));
  }
  return out;
}

// The ends of a range that belong to it.
std::vector<std::string> inside(const StatedRange& r) {
  if (r.open == '{') return r.values;
  std::vector<std::string> out;
  if (r.open == '[') out.push_back(r.values.front());
  if (r.close == ']') out.push_back(r.values.back());
  return out;
}

// Values a text option that holds numbers must refuse, by its check.
std::vector<std::string> outsideText(const std::string& check, const StatedRange& items) {
  if (check == kSizeCheck) {
    return {"0x480",   "640x0",    "-1x480",    "nanxnan", "infx1", "99999999999999999999x1",
            "32769x1", "640",      "640x480x2", "x480",    "+5x5",  "640x-1",
            "1e3x1",   "640x480 ", ""};
  }
  if (check == kSizeListCheck) return {"640x480,0x1", "nan", "640x480,-1x5", "1,2"};
  if (check == kLookaheadCheck) {
    return {"0", "-1", "nan", "inf", "4294967295", "99999999999999999999", "1.5", "", "al"};
  }
  if (check == kLookaheadListCheck) return {"1,0", "4,nan", "all,-1", "1,4294967295"};
  std::vector<std::string> out;
  for (const std::string& bad : outside(items, check == kNumberListCheck)) {
    // An empty item is skipped (as splitList() does), "1,5" is two good items.
    if (!bad.empty() && bad.find(',') == std::string::npos) out.push_back("8," + bad);
  }
  return out;
}

std::string name(const CLI::App& command, const CLI::Option& option) {
  return command.get_name() + " " + option.get_name();
}

TEST(OptionRanges, EveryNumericOptionStatesItsRangeAndRefusesWhatLiesOutside) {
  auto app = commandLine();
  std::size_t numeric = 0, text = 0, refused = 0;
  for (CLI::App* command : app->get_subcommands([](CLI::App*) { return true; })) {
    for (CLI::Option* option : command->get_options()) {
      if (option->get_type_size() == 0 || option->get_expected_max() == 0) continue;  // a flag
      const std::string what = name(*command, *option);
      const std::string type = option->get_type_name();
      std::string check;
      for (const std::string& c : {kNumberCheck, kNumberListCheck, kRealListCheck, kSizeCheck,
                                   kSizeListCheck, kLookaheadCheck, kLookaheadListCheck}) {
        try {
          option->get_validator(c);
          check = c;
        } catch (const CLI::OptionNotFound&) {
        }
      }
      if (type != "TEXT") {
        ASSERT_EQ(check, kNumberCheck) << what << " (" << type << ") is a number without "
                                       << "addNumber()'s check";
      } else if (check.empty()) {
        EXPECT_TRUE(kTextOptions.count(option->get_name()))
            << what << " is text without a check: if it holds a number, check it "
            << "(option_checks.hpp); if not, add it to kTextOptions";
        continue;
      }
      const std::string& help = option->get_description();
      const StatedRange range = statedRange(help);
      std::vector<std::string> bad;
      if (check == kNumberCheck) {
        ++numeric;
        ASSERT_FALSE(range.values.empty()) << what << ": its help states no range: " << help;
        bad = outside(range, wholeType(*option));
        for (const std::string& good : inside(range)) {
          const Outcome o = parse(command->get_name(), option->get_name(), good);
          EXPECT_TRUE(o.parsed) << what << " refused " << good << ", in its range " << range.text
                                << ": " << o.usage_error;
        }
      } else {
        ++text;
        const StatedRange items = statedRange(help, "each in range ");
        if (check == kNumberListCheck || check == kRealListCheck) {
          ASSERT_FALSE(items.values.empty()) << what << ": its help states no range: " << help;
        }
        bad = outsideText(check, items);
      }
      for (const std::string& value : bad) {
        const Outcome o = parse(command->get_name(), option->get_name(), value);
        ++refused;
        ASSERT_FALSE(o.parsed) << what << " accepted '" << value << "'";
        EXPECT_NE(o.usage_error.find(option->get_name() + ":"), std::string::npos)
            << what << " '" << value << "': the message names no option: " << o.usage_error;
        if (value.empty()) continue;  // CLI11 itself: "--frames: 1 required UINT missing"
        EXPECT_NE(o.usage_error.find("'" + value + "'"), std::string::npos)
            << what << " '" << value << "': the message names no value: " << o.usage_error;
        const std::string stated = check == kNumberCheck ? range.text
                                   : check == kNumberListCheck || check == kRealListCheck
                                       ? statedRange(help, "each in range ").text
                                       : "[1, ";
        EXPECT_NE(o.usage_error.find(stated), std::string::npos)
            << what << " '" << value << "': the message names no range: " << o.usage_error;
      }
    }
  }
  std::printf("%zu numeric options and %zu text options holding numbers refused %zu values\n",
              numeric, text, refused);
  // walk, bench, tune, view: some 25 numbers each; calibrate, ddo, export a few.
  EXPECT_GT(numeric, 100u);
  EXPECT_GE(text,
            8u);  // --size (walk, tune, view), --sizes, --lookahead(s), --tiles, --movers-list
  EXPECT_GT(refused, 2000u);
}

TEST(OptionRanges, TheCheckItselfReadsNumbersAsTheRangeSays) {
  EXPECT_EQ(numberProblem("7", closed(1u, 64u)), "");
  EXPECT_EQ(numberProblem("0", closed(1u, 64u)), "'0' is out of range [1, 64]");
  EXPECT_EQ(numberProblem("-0", closed(0u, 64u)), "");
  EXPECT_EQ(numberProblem("+3", closed(0u, 64u)), "");
  EXPECT_EQ(numberProblem("4294967296", closed(0u, 4294967295u)),
            "'4294967296' is out of range [0, 4294967295]");
  EXPECT_EQ(numberProblem("1e3", closed(0u, 64u)), "'1e3' is not a whole number in range [0, 64]");
  EXPECT_EQ(numberProblem(" 5", closed(0u, 64u)), "' 5' is not a number in range [0, 64]");
  EXPECT_EQ(numberProblem("nan", above(0, 1000)), "'nan' is out of range (0, 1000]");
  EXPECT_EQ(numberProblem("1e-400", closed(0.0, 1.0)), "");  // underflows to 0: a number
  EXPECT_EQ(numberProblem("inf", closed(0.0, double(INFINITY))), "");
  EXPECT_EQ(numberProblem("3.5e38", closed(0.0f, float(INFINITY))),
            "'3.5e38' is out of range [0, inf]");  // above the largest float
  EXPECT_EQ(numberProblem("33", oneOf<std::uint32_t>({32, 64})), "'33' is out of range {32, 64}");
  EXPECT_EQ(above(0, 180).text(), "(0, 180]");
  EXPECT_EQ(closed(0.0, 1e9).text(), "[0, 1000000000]");
  EXPECT_EQ(closed(0.0, 0.25).text(), "[0, 0.25]");
}

// The range `walk` states for an option.
StatedRange walkRange(const std::string& option) {
  auto app = commandLine();
  return statedRange(app->get_subcommand("walk")->get_option(option)->get_description());
}

// Where the library has a validator for a setting, the command line's range is the one
// it accepts: the ends the option takes pass the validator, the values just outside fail
// it. So an option check can only be stricter where the library cannot say (a value that
// means nothing to the command, such as more samples than any driver has).
TEST(OptionRanges, TheRangesAreThoseTheLibrarysValidatorsAccept) {
  struct Case {
    const char* option;
    std::function<std::string(double)> problem;  // the validator, the setting at a value
    double just_outside;                         // below the least or above the largest
  };
  const Case cases[] = {
      {"--cpu-threads",
       [](double v) {
         cpu::OcclusionBufferDesc d;
         d.threads = std::uint32_t(v);
         return cpu::validateOcclusionBufferDesc(d);
       },
       65},
      {"--ddo-threads",
       [](double v) {
         ddo::BuildArgs a;
         a.threads = std::uint32_t(v);
         return ddo::validateBuildArgs(a);
       },
       1025},
      {"--ddo-leaf",
       [](double v) {
         ddo::BuildArgs a;
         a.leaf_triangles = std::uint32_t(v);
         return ddo::validateBuildArgs(a);
       },
       0},
      {"--ddo-regions",
       [](double v) {
         ddo::BuildArgs a;
         a.regions = std::uint32_t(v);
         return ddo::validateBuildArgs(a);
       },
       48},
      {"--tile",
       [](double v) {
         return validateGridDesc({1, 1, std::uint32_t(v), {}});
       },
       0},
      {"--full-fraction",
       [](double v) {
         GridApproximation a;
         a.full_free_fraction = float(v);
         return validateGridDesc({64, 64, 32, GridVariant::OcclusionState}, a);
       },
       1},
      {"--budget-ms",
       [](double v) {
         CullerDesc d;
         d.budget_ms = v;
         return validateCullerDesc(d);
       },
       -1},
      {"--row-stride",
       [](double v) {
         GridApproximation a;
         a.row_stride = std::uint32_t(v);
         return validateGridDesc({1, 1, kMaxViewportSide, {}}, a);
       },
       0},
      {"--chc-batch",
       [](double v) {
         QueryScheduleDesc d;
         d.chc_batch = std::uint32_t(v);
         return validateQuerySchedule(QuerySchedule::Chc, d);
       },
       0},
      {"--chc-interval",
       [](double v) {
         QueryScheduleDesc d;
         d.chc_visible_interval = std::uint32_t(v);
         return validateQuerySchedule(QuerySchedule::Chc, d);
       },
       0},
      {"--stat-in-flight",
       [](double v) {
         QueryScheduleDesc d;
         d.stat_in_flight = std::uint32_t(v);
         return validateQuerySchedule(QuerySchedule::Stat, d);
       },
       0},
      {"--stat-base",
       [](double v) {
         QueryScheduleDesc d;
         d.stat_base_frames = std::uint32_t(v);
         return validateQuerySchedule(QuerySchedule::Stat, d);
       },
       0},
      {"--scale",
       [](double v) {
         try {
           checkScale("forest", v, kMaxForestScale);
         } catch (const Error& e) {
           return std::string(e.what());
         }
         return std::string();
       },
       1001},
  };
  for (const Case& c : cases) {
    const StatedRange range = walkRange(c.option);
    ASSERT_FALSE(range.values.empty()) << c.option;
    std::vector<std::string> ends = inside(range);
    if (range.open == '[' && range.close == ')') ends.push_back("0.99999994");  // below 1
    for (const std::string& end : ends) {
      EXPECT_EQ(c.problem(std::stod(end)), "") << c.option << " " << end << " in " << range.text;
    }
    EXPECT_NE(c.problem(c.just_outside), "") << c.option << " " << c.just_outside;
    const Outcome o = parse("walk", c.option, std::to_string(std::int64_t(c.just_outside)));
    EXPECT_FALSE(o.parsed) << c.option << " takes " << c.just_outside
                           << ", which the library refuses";
  }
}

// main() turns a refusal into exit status 2 with the message on stderr, for every
// subcommand alike (view included, whether or not this build has the viewer).
TEST(OptionRanges, ARefusedNumberExitsTwoWithTheMessage) {
  const std::filesystem::path scratch =
      std::filesystem::temp_directory_path() / "logrid_option_range_test";
  std::filesystem::create_directories(scratch);
  const struct {
    std::vector<std::string> args;
    std::string message;
  } cases[] = {
      {{"walk", "--scene", "forest", "--frames", "0"},
       "--frames: '0' is out of range [1, 10000000]"},
      {{"walk", "--scene", "forest", "--fov=nan"}, "--fov: 'nan' is out of range (0, 180)"},
      {{"bench", "--repeat=-1"}, "--repeat: '-1' is out of range [1, 1000]"},
      {{"tune", "--scene", "city", "--size", "0x480"}, "--size: size '0x480' is invalid"},
      {{"view", "--scene", "forest", "--tile=inf"}, "--tile: 'inf' is not a whole number"},
      {{"calibrate", "--size", "99999999999999999999"}, "--size: '99999999999999999999' is out"},
  };
  const bool viewer = commandLine()->get_subcommand("view")->get_option_no_throw("--tile");
  for (const auto& c : cases) {
    if (c.args[0] == "view" && !viewer) continue;  // a build without the viewer: no options
    std::vector<std::string> argv = {LOGRID_BIN};
    argv.insert(argv.end(), c.args.begin(), c.args.end());
    const test::ProcessResult r = test::runProcess(argv, {}, scratch.string());
    EXPECT_EQ(r.exit_code, 2) << c.args[0] << ": " << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace logrid::samples
