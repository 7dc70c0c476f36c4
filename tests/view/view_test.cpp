// `logrid view` driven by a script under Xvfb, as a person would use it: it flies,
// switches method and overlays, takes screenshots, records the flight and quits; the
// screenshots must show the scene, the overlay must change the picture, and the recorded
// path must replay in `logrid walk`. Without a display it must say so, not crash.
//
// Needs Xvfb (scripts/setup.sh installs it); without it the tests are skipped, unless
// LOGRID_REQUIRE_GL=1 (scripts/test.sh), where they fail.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "process.hpp"
#include "scene/camera_path.hpp"

namespace {

using logrid::test::ProcessResult;
using logrid::test::runProcess;
using logrid::test::VirtualDisplay;

const std::string kLogrid = LOGRID_BIN;
const std::string kFlight = std::string(LOGRID_SOURCE_DIR) + "/tests/view/flight.script";

bool glRequired() {
  const char* v = std::getenv("LOGRID_REQUIRE_GL");
  return v && std::string(v) == "1";
}

#define LOGRID_REQUIRE_DISPLAY(x)                                        \
  do {                                                                   \
    if ((x).display().empty()) {                                         \
      if (glRequired()) FAIL() << "no virtual display: " << (x).error(); \
      GTEST_SKIP() << "no virtual display: " << (x).error();             \
    }                                                                    \
  } while (0)

// A fresh folder per test and process.
std::string scratchDir() {
  const testing::TestInfo* info = testing::UnitTest::GetInstance()->current_test_info();
  const std::string dir =
      testing::TempDir() + "logrid_view_" + info->name() + "_" + std::to_string(::getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir + "/out");
  return dir;
}

std::vector<std::string> linesStartingWith(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(prefix, 0) == 0) out.push_back(line.substr(prefix.size()));
  }
  return out;
}

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // top-down rows
  const std::uint8_t* at(int x, int y) const {
    return &rgb[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3];
  }
};

Image readPng(const std::string& path) {
  Image img;
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    ADD_FAILURE() << "cannot read " << path << ": " << OIIO::geterror();
    return img;
  }
  const OIIO::ImageSpec& spec = in->spec();
  img.width = spec.width;
  img.height = spec.height;
  std::vector<std::uint8_t> pixels(std::size_t(spec.width) * std::size_t(spec.height) *
                                   std::size_t(spec.nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, pixels.data()))
      << path;
  img.rgb.resize(std::size_t(spec.width) * std::size_t(spec.height) * 3);
  for (std::size_t i = 0; i < std::size_t(spec.width) * std::size_t(spec.height); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      img.rgb[i * 3 + k] = pixels[i * std::size_t(spec.nchannels) +
                                  std::min<std::size_t>(k, std::size_t(spec.nchannels) - 1)];
    }
  }
  return img;
}

// A blank (or single-colour) window has few colours and no contrast; a rendered forest
// has hundreds of colours (quantised to 5 bits a channel) and a luminance spread of tens.
void expectNotBlank(const Image& img, const std::string& name) {
  std::set<int> colors;
  double sum = 0, sum2 = 0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t* p = img.at(x, y);
      colors.insert((p[0] >> 3) << 10 | (p[1] >> 3) << 5 | (p[2] >> 3));
      const double l = 0.3 * p[0] + 0.59 * p[1] + 0.11 * p[2];
      sum += l;
      sum2 += l * l;
    }
  }
  const double n = double(img.width) * img.height;
  const double deviation = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  EXPECT_GE(colors.size(), 64u) << name << " looks blank";
  EXPECT_GT(deviation, 8.0) << name << " looks blank";
}

// The fraction of pixels whose colours differ by more than a little (24 summed over RGB:
// above any rounding, below any overlay tint).
double differing(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) return 1;
  std::size_t n = 0;
  for (std::size_t i = 0; i + 2 < a.rgb.size(); i += 3) {
    int d = 0;
    for (std::size_t k = 0; k < 3; ++k) d += std::abs(int(a.rgb[i + k]) - int(b.rgb[i + k]));
    n += d > 24;
  }
  return double(n) / double(a.width * a.height);
}

std::string screenshotPath(const std::string& line) { return line.substr(0, line.find(" (")); }

TEST(ViewTest, ScriptedFlightUnderXvfb) {
  VirtualDisplay x;
  LOGRID_REQUIRE_DISPLAY(x);
  const std::string dir = scratchDir();
  const ProcessResult r =
      runProcess({kLogrid, "view", "--scene", "forest", "--scale", "0.1", "--size", "480x360",
                  "--script", kFlight, "--out", dir + "/out"},
                 {{"DISPLAY", x.display()}, {"WAYLAND_DISPLAY", std::nullopt}}, dir);
  ASSERT_EQ(r.signal, 0) << "crashed\n" << r.out << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;

  // Seven screenshots, the last two after the window shrank to 400x300.
  const std::vector<std::string> shots = linesStartingWith(r.out, "view: screenshot ");
  ASSERT_EQ(shots.size(), 7u) << r.out;
  std::vector<Image> images;
  for (std::size_t i = 0; i < shots.size(); ++i) {
    images.push_back(readPng(screenshotPath(shots[i])));
    const Image& img = images.back();
    EXPECT_EQ(img.width, i < 5 ? 480 : 400) << shots[i];
    EXPECT_EQ(img.height, i < 5 ? 360 : 300) << shots[i];
    expectNotBlank(img, shots[i]);
  }
  EXPECT_NE(r.out.find("view: drawable 400x300"), std::string::npos) << r.out;
  // The flight moved the camera: most of the picture changed.
  EXPECT_GT(differing(images[0], images[1]), 0.3);
  // Shots 3 and 4 have the same camera and no panel; 4 has the tile grid and boxes.
  EXPECT_GT(differing(images[2], images[3]), 0.5) << "the overlay did not change the picture";

  // The method switched (M): two different methods were applied.
  std::set<std::string> methods;
  for (const std::string& line : linesStartingWith(r.out, "view: method ")) {
    methods.insert(line.substr(0, line.find(',')));
  }
  EXPECT_GE(methods.size(), 2u) << r.out;
  // Verify ran for the frames after V, and the exact methods missed nothing.
  const std::vector<std::string> summary = linesStartingWith(r.out, "view: ");
  ASSERT_FALSE(summary.empty());
  EXPECT_NE(summary.back().find("frames checked, 0 visible objects missed"), std::string::npos)
      << summary.back();

  // The recorded flight is a camera path that walk replays, checked by the oracle.
  const std::vector<std::string> recorded = linesStartingWith(r.out, "view: recorded ");
  ASSERT_EQ(recorded.size(), 1u) << r.out;
  const std::string path_file = recorded[0].substr(0, recorded[0].find(' '));
  const logrid::samples::CameraPath path = logrid::samples::CameraPath::fromJsonFile(path_file);
  EXPECT_GE(path.keys().size(), 10u);
  const glm::dvec3 a = path.keys().front().position, b = path.keys().back().position;
  EXPECT_GT(std::hypot(a.x - b.x, a.y - b.y, a.z - b.z), 1.0) << "the flight did not move";
  const ProcessResult walk =
      runProcess({kLogrid, "walk", "--scene", "forest", "--scale", "0.1", "--path", path_file,
                  "--frames", "6", "--size", "160x120", "--verify"},
                 {}, dir);
  EXPECT_EQ(walk.signal, 0);
  EXPECT_EQ(walk.exit_code, 0) << walk.out << walk.err;
  EXPECT_NE(walk.out.find(", 0 missed"), std::string::npos) << walk.out;
}

// With an approximate setting, verify finds visible objects the method did not draw and
// flashes them red; such misses are the measured trade, so the exit code stays 0.
TEST(ViewTest, VerifyFlashesMissedObjects) {
  VirtualDisplay x;
  LOGRID_REQUIRE_DISPLAY(x);
  const std::string dir = scratchDir();
  {
    std::ofstream script(dir + "/verify.script");
    script << "0 key Tab\n0 key V\n6 key F12\n7 key Escape\n";
  }
  const ProcessResult r =
      runProcess({kLogrid, "view", "--scene", "forest", "--scale", "0.1", "--size", "320x240",
                  "--method", "log-zfar", "--visible-pixels", "4000", "--script",
                  dir + "/verify.script", "--out", dir + "/out"},
                 {{"DISPLAY", x.display()}, {"WAYLAND_DISPLAY", std::nullopt}}, dir);
  ASSERT_EQ(r.signal, 0) << r.out << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("visible objects not drawn"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(0 by exact settings)"), std::string::npos) << r.out;
  const std::vector<std::string> shots = linesStartingWith(r.out, "view: screenshot ");
  ASSERT_EQ(shots.size(), 1u) << r.out;
  const Image img = readPng(screenshotPath(shots[0]));
  std::size_t red = 0;  // the flash: (255, 30, 30) outlines and a translucent fill
  for (int y = 0; y < img.height; ++y) {
    for (int xx = 0; xx < img.width; ++xx) {
      const std::uint8_t* p = img.at(xx, y);
      red += p[0] > 200 && p[1] < 60 && p[2] < 60;
    }
  }
  EXPECT_GE(red, 40u) << "no missed object flashed red in " << shots[0];
}

TEST(ViewTest, WithoutADisplayItSaysSoAndExits1) {
  const std::string dir = scratchDir();
  for (const std::optional<std::string>& display :
       {std::optional<std::string>{}, std::optional<std::string>(":9999")}) {
    const ProcessResult r =
        runProcess({kLogrid, "view", "--scene", "forest", "--scale", "0.05", "--out", dir + "/out"},
                   {{"DISPLAY", display}, {"WAYLAND_DISPLAY", std::nullopt}}, dir);
    EXPECT_EQ(r.signal, 0) << "crashed: " << r.err;
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_NE(r.err.find("cannot open a window"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("xvfb-run"), std::string::npos) << r.err;
    if (!display) {
      EXPECT_NE(r.err.find("DISPLAY"), std::string::npos) << r.err;
    }
  }
}

TEST(ViewTest, BadOptionsExit2BeforeAnyWindow) {
  const std::string dir = scratchDir();
  {
    std::ofstream script(dir + "/bad.script");
    script << "0 key W\n1 key Hyper\n";
  }
  // No display is needed to be told about bad input.
  const logrid::test::EnvChanges no_display = {{"DISPLAY", std::nullopt},
                                               {"WAYLAND_DISPLAY", std::nullopt}};
  ProcessResult r = runProcess(
      {kLogrid, "view", "--scene", "forest", "--script", dir + "/bad.script"}, no_display, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("line 2"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("unknown key 'Hyper'"), std::string::npos) << r.err;
  r = runProcess({kLogrid, "view", "--scene", "forest", "--method", "magic"}, no_display, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("method 'magic'"), std::string::npos) << r.err;
  r = runProcess({kLogrid, "view", "--scene", "forest", "--size", "0x10"}, no_display, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("size '0x10'"), std::string::npos) << r.err;
  // A repeated option is no usage error, the last one wins, as in walk, bench and tune.
  r = runProcess({kLogrid, "view", "--scene", "forest", "--size", "64x48", "--method", "magic",
                  "--method", "log-state", "--size", "0x10"},
                 no_display, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("size '0x10'"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("magic"), std::string::npos) << r.err;
}

}  // namespace
