#include "scene/camera_path.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/error.hpp"
#include "logrid/glm_camera.hpp"

namespace {

// The samples keep their vectors in GLM.
using DVec3 = glm::dvec3;
using logrid::Error;
using logrid::ErrorCode;
using logrid::samples::CameraKey;
using logrid::samples::CameraPath;
using logrid::samples::CameraPose;

double distance(DVec3 a, DVec3 b) { return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z); }
bool isFinite(DVec3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
bool same(DVec3 a, DVec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

void expectSame(DVec3 actual, DVec3 expected) {
  EXPECT_EQ(actual.x, expected.x);
  EXPECT_EQ(actual.y, expected.y);
  EXPECT_EQ(actual.z, expected.z);
}

void expectPoseIsKey(const CameraPose& pose, const CameraKey& key, DVec3 up = {0, 1, 0}) {
  expectSame(pose.position, key.position);
  expectSame(pose.look_at, key.look_at);
  expectSame(pose.up, up);
}

// A pose is usable when logrid's own lookAt accepts it.
void expectUsable(const CameraPose& pose, double time) {
  ASSERT_TRUE(isFinite(pose.position)) << "time " << time;
  ASSERT_TRUE(isFinite(pose.look_at)) << "time " << time;
  ASSERT_FALSE(same(pose.position, pose.look_at)) << "time " << time;
  EXPECT_NO_THROW(logrid::lookAt(logrid::toDVec3(pose.position), logrid::toDVec3(pose.look_at),
                                 logrid::toDVec3(pose.up)))
      << "time " << time;
}

// Runs `f`, expects a logrid::Error with `code` and returns its message.
std::string errorOf(const std::function<void()>& f, ErrorCode code) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "expected a logrid::Error";
  return {};
}

void expectContains(const std::string& message, std::initializer_list<const char*> parts) {
  for (const char* part : parts) {
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
  }
}

std::string jsonError(const std::string& text) {
  return errorOf([&] { CameraPath::fromJsonText(text, "test.json"); }, ErrorCode::BadInput);
}

std::string constructorError(std::vector<CameraKey> keys, DVec3 up = {0, 1, 0}) {
  return errorOf([&] { const CameraPath path(keys, up); }, ErrorCode::InvalidArgument);
}

// Uneven spacing in space and time, with turns, so the spline has something to do.
std::vector<CameraKey> wavyKeys() {
  return {{{0, 0, 0}, {0, 0, -1}, 0.0},
          {{3, 1, 0}, {3, 0, -5}, 1.0},
          {{4, 1, 4}, {0, 0, 4}, 2.5},
          {{4, 2, 4.1}, {8, 0, 4}, 3.0},
          {{-2, 0, 8}, {-2, 0, 0}, 7.0}};
}

// A unique file name per test and process, so parallel ctest runs do not collide.
std::string tempPath(const std::string& suffix) {
  const testing::TestInfo* info = testing::UnitTest::GetInstance()->current_test_info();
  return testing::TempDir() + "camera_path_" + info->name() + "_" + std::to_string(::getpid()) +
         suffix;
}

TEST(CameraPathTest, HitsKeysExactly) {
  const std::vector<CameraKey> keys = wavyKeys();
  const CameraPath path(keys);
  ASSERT_EQ(path.keys().size(), keys.size());
  EXPECT_EQ(path.duration(), 7.0);
  for (const CameraKey& key : keys) expectPoseIsKey(path.at(key.time), key);
}

TEST(CameraPathTest, IsContinuous) {
  const CameraPath path(wavyKeys());
  const int steps = 100000;
  const double dt = path.duration() / steps;
  double max_move = 0;
  double max_turn = 0;
  CameraPose previous = path.at(0);
  for (int i = 1; i <= steps; ++i) {
    const CameraPose pose = path.at(dt * i);
    ASSERT_TRUE(isFinite(pose.position) && isFinite(pose.look_at)) << "step " << i;
    max_move = std::max(max_move, distance(pose.position, previous.position));
    max_turn = std::max(max_turn, distance(pose.look_at, previous.look_at));
    previous = pose;
  }
  // The path spans ~10 units in 7 s, so 70 us steps should move about 1e-4, never 1e-2.
  EXPECT_LT(max_move, 1e-2);
  EXPECT_LT(max_turn, 1e-2);
  // No jump at the keys: both sides converge to the key.
  for (const CameraKey& key : wavyKeys()) {
    for (double offset : {-1e-9, 1e-9}) {
      const CameraPose pose = path.at(key.time + offset);
      EXPECT_LT(distance(pose.position, key.position), 1e-6) << key.time + offset;
      EXPECT_LT(distance(pose.look_at, key.look_at), 1e-6) << key.time + offset;
    }
  }
}

TEST(CameraPathTest, InterpolatesBetweenKeys) {
  // Four collinear keys, evenly timed and spaced: the spline stays on the line, moves
  // forward only, and passes the middle of the middle segment half way. (The end segments
  // ease in and out: the duplicated end points give the path zero speed at its ends.)
  const CameraPath path({{{0, 0, 0}, {0, 0, -1}, 0},
                         {{1, 0, 0}, {1, 0, -1}, 1},
                         {{2, 0, 0}, {2, 0, -1}, 2},
                         {{3, 0, 0}, {3, 0, -1}, 3}});
  double previous_x = 0;
  for (int i = 0; i <= 300; ++i) {
    const CameraPose pose = path.at(i * 0.01);
    EXPECT_EQ(pose.position.y, 0.0);
    EXPECT_EQ(pose.position.z, 0.0);
    EXPECT_GE(pose.position.x, previous_x);
    previous_x = pose.position.x;
  }
  EXPECT_NEAR(path.at(1.5).position.x, 1.5, 1e-12);
  EXPECT_NEAR(path.at(1.5).look_at.x, 1.5, 1e-12);
  EXPECT_LT(path.at(0.5).position.x, 0.5);  // easing in
  EXPECT_GT(path.at(2.5).position.x, 2.5);  // easing out
}

TEST(CameraPathTest, AssignsTimesByDistanceForConstantSpeed) {
  const CameraPath path = CameraPath::fromJsonText(R"({"keys": [
      {"position": [0, 0, 0], "look_at": [0, 0, -1]},
      {"position": [3, 4, 0], "look_at": [3, 4, -1]},
      {"position": [3, 4, 12], "look_at": [3, 4, 11]},
      {"position": [3, 4, 13], "look_at": [3, 4, 12]}]})");
  ASSERT_EQ(path.keys().size(), 4u);
  EXPECT_EQ(path.keys()[0].time, 0.0);
  EXPECT_EQ(path.keys()[1].time, 5.0);
  EXPECT_EQ(path.keys()[2].time, 17.0);
  EXPECT_EQ(path.keys()[3].time, 18.0);
  EXPECT_EQ(path.duration(), 18.0);
  // Frames spread evenly in time then cover equal distances per key segment.
  expectSame(path.frame(5, 19).position, DVec3{3, 4, 0});
}

TEST(CameraPathTest, SpacesKeysEvenlyWhenTheCameraOnlyTurns) {
  const CameraPath path = CameraPath::fromJsonText(R"({"keys": [
      {"position": [1, 1, 1], "look_at": [1, 1, 0]},
      {"position": [1, 1, 1], "look_at": [2, 1, 1]},
      {"position": [1, 1, 1], "look_at": [1, 1, 2]}]})");
  ASSERT_EQ(path.keys().size(), 3u);
  EXPECT_EQ(path.keys()[1].time, 1.0);
  EXPECT_EQ(path.keys()[2].time, 2.0);
  for (int i = 0; i <= 100; ++i) {
    const CameraPose pose = path.at(i * 0.02);
    expectUsable(pose, i * 0.02);
    expectSame(pose.position, DVec3{1, 1, 1});
  }
}

TEST(CameraPathTest, TurnInPlaceSegmentsGetTheMeanMovingTime) {
  // Moving segments of 4 and 6; the turn in place gets their mean, 5.
  const CameraPath path = CameraPath::fromJsonText(R"({"keys": [
      {"position": [0, 0, 0], "look_at": [0, 0, -1]},
      {"position": [0, 0, 0], "look_at": [1, 0, 0]},
      {"position": [4, 0, 0], "look_at": [5, 0, 0]},
      {"position": [4, 0, 6], "look_at": [4, 0, 7]}]})");
  ASSERT_EQ(path.keys().size(), 4u);
  EXPECT_EQ(path.keys()[1].time, 5.0);
  EXPECT_EQ(path.keys()[2].time, 9.0);
  EXPECT_EQ(path.keys()[3].time, 15.0);
}

TEST(CameraPathTest, ClampsTimeToThePath) {
  const std::vector<CameraKey> keys = wavyKeys();
  const CameraPath path(keys);
  const double inf = std::numeric_limits<double>::infinity();
  for (double t : {-1.0, -1e300, -inf}) expectPoseIsKey(path.at(t), keys.front());
  for (double t : {7.5, 1e300, inf}) expectPoseIsKey(path.at(t), keys.back());
  const std::string message = errorOf([&] { path.at(std::nan("")); }, ErrorCode::InvalidArgument);
  expectContains(message, {"nan"});
}

TEST(CameraPathTest, SingleKey) {
  const CameraKey key{{1, 2, 3}, {1, 2, 0}, 4.0};
  const CameraPath path({key});
  EXPECT_FALSE(path.empty());
  EXPECT_EQ(path.duration(), 0.0);
  for (double t : {-10.0, 4.0, 10.0}) expectPoseIsKey(path.at(t), key);
  expectPoseIsKey(path.frame(0, 1), key);
  expectPoseIsKey(path.frame(3, 7), key);
  expectPoseIsKey(path.frame(6, 7), key);

  const CameraPath from_json =
      CameraPath::fromJsonText(R"({"keys": [{"position": [1, 2, 3], "look_at": [1, 2, 0]}]})");
  EXPECT_EQ(from_json.duration(), 0.0);
  expectPoseIsKey(from_json.at(1.0), {{1, 2, 3}, {1, 2, 0}, 0.0});
}

TEST(CameraPathTest, EmptyPath) {
  const CameraPath path;
  EXPECT_TRUE(path.empty());
  EXPECT_EQ(path.duration(), 0.0);
  expectContains(errorOf([&] { path.at(0); }, ErrorCode::InvalidArgument), {"empty"});
  expectContains(errorOf([&] { path.frame(0, 2); }, ErrorCode::InvalidArgument), {"empty"});
}

TEST(CameraPathTest, CoincidentKeysGiveNoNaN) {
  // A pause (two identical keys), a turn in place, a move, another pause.
  const std::vector<CameraKey> keys = {{{0, 0, 0}, {0, 0, -1}, 0}, {{0, 0, 0}, {0, 0, -1}, 1},
                                       {{0, 0, 0}, {1, 0, 0}, 2},  {{5, 0, 0}, {6, 0, 0}, 3},
                                       {{5, 0, 0}, {6, 0, 0}, 4},  {{5, 0, 0}, {6, 0, 0}, 5}};
  const CameraPath path(keys);
  for (int i = -10; i <= 5010; ++i) expectUsable(path.at(i * 0.001), i * 0.001);
  // During a pause the camera stays put.
  expectSame(path.at(0.5).position, keys[0].position);
  expectSame(path.at(0.5).look_at, keys[0].look_at);
  expectSame(path.at(4.5).position, keys[4].position);
  for (const CameraKey& key : keys) expectPoseIsKey(path.at(key.time), key);
}

TEST(CameraPathTest, CameraFlyingThroughItsTargetStaysUsable) {
  // Both keys look at the origin from either side; half way the camera is on it.
  const CameraPath path({{{-1, 0, 0}, {0, 0, 0}, 0}, {{1, 0, 0}, {0, 0, 0}, 1}});
  const CameraPose middle = path.at(0.5);
  expectSame(middle.position, DVec3{0, 0, 0});
  expectUsable(middle, 0.5);
  // The replacement direction is one of the keys' view directions.
  EXPECT_EQ(middle.look_at.y, 0.0);
  EXPECT_EQ(middle.look_at.z, 0.0);
  for (int i = 0; i <= 10000; ++i) expectUsable(path.at(i * 1e-4), i * 1e-4);
}

TEST(CameraPathTest, RandomPathsAreFiniteAndUsable) {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> coordinate(-10, 10);
  std::uniform_int_distribution<int> pick(0, 3);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<CameraKey> keys;
    double time = coordinate(rng);
    const int count = 1 + trial % 9;
    for (int k = 0; k < count; ++k) {
      CameraKey key;
      // Repeat positions and look-at points often: that is where the spline degenerates.
      key.position = keys.empty() || pick(rng) != 0
                         ? DVec3{coordinate(rng), coordinate(rng), coordinate(rng)}
                         : keys.back().position;
      key.look_at = keys.empty() || pick(rng) != 0
                        ? DVec3{coordinate(rng), coordinate(rng), coordinate(rng)}
                        : keys.back().look_at;
      if (same(key.position, key.look_at)) key.look_at.x += 1;
      time += pick(rng) == 0 ? 1e-9 : 0.5 + pick(rng);
      key.time = time;
      keys.push_back(key);
    }
    const CameraPath path(keys);
    for (int i = 0; i <= 500; ++i) {
      const CameraPose pose = path.frame(static_cast<std::size_t>(i), 501);
      ASSERT_TRUE(isFinite(pose.position) && isFinite(pose.look_at)) << trial << " " << i;
      ASSERT_FALSE(same(pose.position, pose.look_at)) << trial << " " << i;
    }
  }
}

TEST(CameraPathTest, FramesSpreadOverThePath) {
  const std::vector<CameraKey> keys = {
      {{0, 0, 0}, {0, 0, -1}, 2}, {{2, 0, 0}, {2, 0, -1}, 4}, {{2, 0, 2}, {2, 0, 1}, 10}};
  const CameraPath path(keys);
  expectPoseIsKey(path.frame(0, 5), keys.front());
  expectPoseIsKey(path.frame(4, 5), keys.back());
  expectSame(path.frame(2, 5).position, path.at(6).position);
  expectSame(path.frame(1, 5).look_at, path.at(4).look_at);
  expectPoseIsKey(path.frame(0, 1), keys.front());
  expectContains(errorOf([&] { path.frame(0, 0); }, ErrorCode::InvalidArgument), {"frames == 0"});
  expectContains(errorOf([&] { path.frame(5, 5); }, ErrorCode::InvalidArgument),
                 {"frame 5", "5 frames"});
}

TEST(CameraPathTest, PosesCarryThePathsUp) {
  const CameraPath path({{{0, 0, 0}, {0, 1, 0}, 0}, {{1, 0, 0}, {1, 1, 0}, 1}}, {0, 0, 1});
  expectSame(path.at(0).up, DVec3{0, 0, 1});
  expectSame(path.at(0.3).up, DVec3{0, 0, 1});
  expectSame(path.frame(1, 2).up, DVec3{0, 0, 1});
}

TEST(CameraPathTest, ConstructorNamesTheProblem) {
  const double nan = std::nan("");
  const double inf = std::numeric_limits<double>::infinity();
  const CameraKey good{{0, 0, 0}, {0, 0, -1}, 0};
  expectContains(constructorError({}), {"camera path:", "no keys"});
  expectContains(constructorError({good, {{nan, 0, 0}, {0, 0, -1}, 1}}),
                 {"key 1", "non-finite position", "(nan, 0, 0)"});
  expectContains(constructorError({{{0, 0, 0}, {0, inf, 0}, 0}}),
                 {"key 0", "non-finite look_at", "(0, inf, 0)"});
  expectContains(constructorError({good, {{1, 0, 0}, {2, 0, 0}, 1}, {{1, 2, 3}, {1, 2, 3}, 2}}),
                 {"key 2 has position == look_at (1, 2, 3)", "direction"});
  expectContains(constructorError({{{0, 0, 0}, {1e-200, 0, 0}, 0}}),
                 {"key 0", "1e-200", "direction"});
  expectContains(constructorError({{{1e200, 0, 0}, {0, 0, 0}, 0}}),
                 {"key 0", "(1e+200, 0, 0)", "out of range"});
  expectContains(constructorError({good, {{1, 0, 0}, {2, 0, 0}, 1}, {{2, 0, 0}, {3, 0, 0}, 1}}),
                 {"key 2 has time 1", "key 1's time 1", "increase strictly"});
  expectContains(constructorError({good, {{1, 0, 0}, {2, 0, 0}, -0.5}}),
                 {"key 1 has time -0.5", "key 0's time 0"});
  expectContains(constructorError({good, {{1, 0, 0}, {2, 0, 0}, nan}}),
                 {"key 1 has time nan", "finite"});
  expectContains(constructorError({good}, {0, 0, 0}), {"up (0, 0, 0)", "length"});
  expectContains(constructorError({good}, {0, nan, 0}), {"up (0, nan, 0)", "finite"});
}

TEST(CameraPathJsonTest, ReadsEveryField) {
  const CameraPath path = CameraPath::fromJsonText(R"({
      "comment": "unknown fields are ignored", "extra": [1, {"nested": [[], {}]}],
      "up": [0, 0, 1],
      "keys": [
        {"position": [1, 2, 3], "look_at": [4, 5, 6.5], "time": 1, "note": {"a": [1]}},
        {"position": [-1e3, 0.25, 3], "look_at": [0, 0, 0], "time": 2.5}
      ]})",
                                                   "inline");
  ASSERT_EQ(path.keys().size(), 2u);
  expectSame(path.keys()[0].position, DVec3{1, 2, 3});
  expectSame(path.keys()[0].look_at, DVec3{4, 5, 6.5});
  EXPECT_EQ(path.keys()[0].time, 1.0);
  expectSame(path.keys()[1].position, DVec3{-1e3, 0.25, 3});
  EXPECT_EQ(path.keys()[1].time, 2.5);
  EXPECT_EQ(path.duration(), 1.5);
  expectSame(path.at(2).up, DVec3{0, 0, 1});
}

TEST(CameraPathJsonTest, RoundTripsKeysWrittenAsText) {
  const std::vector<CameraKey> keys = wavyKeys();
  std::string text = "{\"keys\": [";
  char number[64];
  auto write = [&](double v) {
    std::snprintf(number, sizeof number, "%.17g", v);
    text += number;
  };
  auto writeVector = [&](DVec3 v) {
    text += "[";
    write(v.x), text += ", ", write(v.y), text += ", ", write(v.z);
    text += "]";
  };
  for (std::size_t i = 0; i < keys.size(); ++i) {
    text += i ? ", {\"position\": " : "{\"position\": ";
    writeVector(keys[i].position);
    text += ", \"look_at\": ";
    writeVector(keys[i].look_at);
    text += ", \"time\": ";
    write(keys[i].time / 3);  // thirds are not exact in binary or decimal
    text += "}";
  }
  text += "]}";
  const CameraPath path = CameraPath::fromJsonText(text);
  ASSERT_EQ(path.keys().size(), keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    expectSame(path.keys()[i].position, keys[i].position);
    expectSame(path.keys()[i].look_at, keys[i].look_at);
    EXPECT_EQ(path.keys()[i].time, keys[i].time / 3);
    expectPoseIsKey(path.at(keys[i].time / 3), keys[i]);
  }
}

TEST(CameraPathJsonTest, SyntaxErrorsGiveTheBytePosition) {
  const std::string message = jsonError(R"({"keys": x})");
  expectContains(message, {"camera path 'test.json'", "invalid JSON at byte 10", "x'"});
  expectContains(jsonError(""), {"invalid JSON at byte 1", "end of input"});
  expectContains(jsonError(R"({"keys": []} ])"), {"invalid JSON at byte 14"});
  expectContains(jsonError("{\"keys\": [\"\xff\"]}"), {"invalid JSON at byte 12"});
  // An unterminated string is quoted back only in part.
  const std::string long_message = jsonError("{\"keys\": \"" + std::string(100000, 'a'));
  expectContains(long_message, {"invalid JSON at byte 100011", "..."});
  EXPECT_LT(long_message.size(), 1000u);
  // JSON has no infinity, and nlohmann refuses literals that overflow a double.
  expectContains(jsonError(R"({"keys": [{"position": [1e999, 0, 0], "look_at": [0, 0, 1]}]})"),
                 {"invalid JSON at byte 29", "1e999"});
}

TEST(CameraPathJsonTest, StructureErrorsNameTheFieldAndKey) {
  const std::string p = R"("position": [0, 0, 0])";
  const std::string l = R"("look_at": [0, 0, 1])";
  expectContains(jsonError("[1, 2]"), {"test.json", "document is an array", "object"});
  expectContains(jsonError(R"({"up": [0, 1, 0]})"), {"no \"keys\""});
  expectContains(jsonError(R"({"keys": {}})"), {"\"keys\" is an object", "array"});
  expectContains(jsonError(R"({"keys": []})"), {"no keys"});
  expectContains(jsonError(R"({"keys": [1]})"), {"key 0 is a number", "object"});
  expectContains(jsonError(R"({"keys": [{)" + p + "," + l + R"(}, {)" + l + "}]}"),
                 {"key 1 has no \"position\""});
  expectContains(jsonError(R"({"keys": [{)" + p + "}]}"), {"key 0 has no \"look_at\""});
  expectContains(jsonError(R"({"keys": [{"position": "here", )" + l + "}]}"),
                 {"key 0 \"position\" is a string", "[x, y, z]"});
  expectContains(jsonError(R"({"keys": [{"position": [1, 2], )" + l + "}]}"),
                 {"key 0 \"position\" has 2 numbers"});
  expectContains(jsonError(R"({"keys": [{"position": [1, 2, 3, 4], )" + l + "}]}"),
                 {"key 0 \"position\" has more than 3 numbers"});
  expectContains(jsonError(R"({"keys": [{)" + p + R"(, "look_at": [1, null, 2]}]})"),
                 {"key 0 \"look_at\" element 1 is null"});
  expectContains(jsonError(R"({"keys": [{)" + p + "," + l + R"(, "time": 0}, {)" + p + "," + l +
                           R"(, "time": "1"}]})"),
                 {"key 1 \"time\" is a string", "number"});
  expectContains(jsonError(R"({"keys": [{)" + p + "," + l + "," + p + "}]}"),
                 {"key 0 \"position\" appears twice"});
  expectContains(jsonError(R"({"keys": [], "keys": []})"), {"\"keys\" appears twice"});
  expectContains(jsonError(R"({"up": [0, 1], "keys": [{)" + p + "," + l + "}]}"),
                 {"\"up\" has 2 numbers"});
  expectContains(jsonError(R"({"up": true, "keys": [{)" + p + "," + l + "}]}"),
                 {"\"up\" is a boolean"});
}

TEST(CameraPathJsonTest, TimesForAllKeysOrNone) {
  const std::string a = R"({"position": [0, 0, 0], "look_at": [0, 0, 1])";
  const std::string b = R"({"position": [1, 0, 0], "look_at": [1, 0, 1])";
  expectContains(jsonError(R"({"keys": [)" + a + R"(, "time": 0}, )" + b + "}]}"),
                 {"key 1 has no \"time\" but key 0 has one", "every key"});
  expectContains(jsonError(R"({"keys": [)" + a + "}, " + b + R"(, "time": 1}]})"),
                 {"key 1 has a \"time\" but key 0 has none"});
}

TEST(CameraPathJsonTest, ValueChecksBecomeBadInput) {
  expectContains(jsonError(R"({"keys": [{"position": [0, 0, 0], "look_at": [0, 0, 1]},
                                        {"position": [1, 2, 3], "look_at": [1, 2, 3]}]})"),
                 {"camera path 'test.json'", "key 1 has position == look_at (1, 2, 3)"});
  expectContains(jsonError(R"({"keys": [{"position": [0, 0, 0], "look_at": [0, 0, 1], "time": 3},
                             {"position": [1, 0, 0], "look_at": [1, 0, 1], "time": 3}]})"),
                 {"key 1 has time 3", "increase strictly"});
  expectContains(jsonError(R"({"keys": [{"position": [1e200, 0, 0], "look_at": [0, 0, 1]}]})"),
                 {"key 0", "position (1e+200, 0, 0)", "out of range"});
  expectContains(jsonError(R"({"up": [0, 0, 0], "keys": [{"position": [0, 0, 0],
                                                          "look_at": [0, 0, 1]}]})"),
                 {"up (0, 0, 0)"});
}

TEST(CameraPathJsonTest, RefusesTooManyKeys) {
  const std::string key = R"({"position":[0,0,0],"look_at":[1,0,0]},)";
  std::string text;
  text.reserve(key.size() * 1000001 + 16);
  text += "{\"keys\":[";
  for (int i = 0; i < 1000001; ++i) text += key;
  // The key limit stops reading early: the broken text after the last key is never
  // reached, so the error is about the keys, not the syntax.
  text += "this is not JSON";
  expectContains(jsonError(text), {"more than 1000000 keys"});
}

TEST(CameraPathJsonTest, RefusesTextOver64MiB) {
  const std::string text(std::size_t{64} * 1024 * 1024 + 1, ' ');
  expectContains(jsonError(text), {"64 MiB"});
}

TEST(CameraPathJsonTest, GarbageOnlyEverThrowsError) {
  std::mt19937 rng(12345);
  const std::string valid = R"({"up": [0, 1, 0], "keys": [
      {"position": [0, 0, 0], "look_at": [0, 0, -1], "time": 0},
      {"position": [1, 0, 0], "look_at": [1, 0, -1], "time": 1.5},
      {"position": [1, 0, 0], "look_at": [2, 0, 0], "time": 2}]})";
  const std::string alphabet = "{}[]\":,. -+0123456789eE\\ntruefalsposiok_amelu\x01\xff";
  std::uniform_int_distribution<std::size_t> length(0, 80);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> edits(1, 6);
  int accepted = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    std::string text;
    if (trial % 3 == 0) {  // random bytes
      text.resize(length(rng));
      for (char& c : text) c = static_cast<char>(byte(rng));
    } else if (trial % 3 == 1) {  // random JSON-ish tokens
      const std::size_t n = length(rng);
      for (std::size_t i = 0; i < n; ++i) text += alphabet[rng() % alphabet.size()];
    } else {  // a valid document with a few edits: reaches the deeper checks
      text = valid;
      for (int e = edits(rng); e > 0; --e) {
        const std::size_t at = rng() % (text.size() + 1);
        const char c = alphabet[rng() % alphabet.size()];
        switch (rng() % 3) {
          case 0: text.insert(text.begin() + static_cast<std::ptrdiff_t>(at), c); break;
          case 1:
            if (at < text.size()) text.erase(at, 1);
            break;
          default:
            if (at < text.size()) text[at] = c;
        }
      }
    }
    try {
      const CameraPath path = CameraPath::fromJsonText(text);
      ++accepted;
      for (int i = 0; i <= 20; ++i) {
        const CameraPose pose = path.frame(static_cast<std::size_t>(i), 21);
        ASSERT_TRUE(isFinite(pose.position) && isFinite(pose.look_at)) << text;
        ASSERT_FALSE(same(pose.position, pose.look_at)) << text;
      }
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::BadInput) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "non-logrid exception " << e.what() << " for: " << text;
    }
  }
  EXPECT_GT(accepted, 0) << "the mutations should sometimes keep the document valid";
}

TEST(CameraPathFileTest, ReadsATemporaryFile) {
  const std::string path = tempPath(".json");
  {
    std::ofstream out(path, std::ios::binary);
    out << R"({"keys": [{"position": [0, 0, 0], "look_at": [0, 0, -1]},
                        {"position": [0, 0, 4], "look_at": [0, 0, 3]}]})";
  }
  const CameraPath loaded = CameraPath::fromJsonFile(path);
  ASSERT_EQ(loaded.keys().size(), 2u);
  EXPECT_EQ(loaded.duration(), 4.0);

  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << R"({"keys": [{"position": [0, 0, 0]}]})";
  }
  const std::string message = errorOf([&] { CameraPath::fromJsonFile(path); }, ErrorCode::BadInput);
  expectContains(message, {path.c_str(), "key 0 has no \"look_at\""});
  std::filesystem::remove(path);
}

TEST(CameraPathFileTest, MissingFileIsAnEnvironmentError) {
  const std::string path = tempPath("_missing.json");
  std::filesystem::remove(path);
  const std::string message =
      errorOf([&] { CameraPath::fromJsonFile(path); }, ErrorCode::Environment);
  expectContains(message, {path.c_str(), "no such file"});
  expectContains(
      errorOf([&] { CameraPath::fromJsonFile(testing::TempDir()); }, ErrorCode::Environment),
      {"directory"});
}

TEST(CameraPathFileTest, RefusesFilesOver64MiB) {
  const std::string path = tempPath("_huge.json");
  { std::ofstream out(path, std::ios::binary); }
  // Sparse: no 64 MiB actually written to disk.
  std::filesystem::resize_file(path, std::uintmax_t{64} * 1024 * 1024 + 1);
  const std::string message = errorOf([&] { CameraPath::fromJsonFile(path); }, ErrorCode::BadInput);
  expectContains(message, {path.c_str(), "64 MiB"});
  std::filesystem::remove(path);
}

}  // namespace

namespace logrid::samples {
namespace {

TEST(CameraPathUntimedTest, KeysThatAllLeaveTimeAtZeroAreSpacedAtConstantSpeed) {
  const CameraPath path(
      {{{0, 0, 0}, {0, 0, -1}, 0}, {{3, 0, 0}, {3, 0, -1}, 0}, {{4, 0, 0}, {4, 0, -1}, 0}});
  ASSERT_EQ(path.keys().size(), 3u);
  EXPECT_EQ(path.keys()[0].time, 0.0);
  EXPECT_DOUBLE_EQ(path.keys()[1].time, 3.0);
  EXPECT_DOUBLE_EQ(path.keys()[2].time, 4.0);
  // Some, but not all, times zero: still strict.
  EXPECT_THROW(
      CameraPath(
          {{{0, 0, 0}, {0, 0, -1}, 0}, {{3, 0, 0}, {3, 0, -1}, 0}, {{4, 0, 0}, {4, 0, -1}, 2}}),
      Error);
}

}  // namespace
}  // namespace logrid::samples
