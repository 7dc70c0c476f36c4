// The configuration file (logrid/config.hpp): what formatCullerConfig writes reads back
// as written, and every kind of bad file is refused with a message naming the file and
// the key.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "expect_error.hpp"
#include "logrid/config.hpp"
#include "logrid/error.hpp"

namespace logrid {
namespace {

CullerConfig unusual() {
  CullerConfig c;
  c.source = "pbo";
  c.culler.method = Method::LogZfar;
  c.culler.tile_size = 16;
  c.culler.lookahead = 64;
  c.culler.temporal_coherence = true;
  c.culler.detect_colliding = true;
  c.culler.approximation.visible_pixels = 0;
  c.culler.approximation.full_free_fraction = 0;
  c.culler.approximation.row_stride = 2;
  return c;
}

void expectSame(const CullerConfig& a, const CullerConfig& b) {
  EXPECT_EQ(a.source, b.source);
  EXPECT_EQ(a.culler.method, b.culler.method);
  EXPECT_EQ(a.culler.tile_size, b.culler.tile_size);
  EXPECT_EQ(a.culler.lookahead, b.culler.lookahead);
  EXPECT_EQ(a.culler.temporal_coherence, b.culler.temporal_coherence);
  EXPECT_EQ(a.culler.detect_colliding, b.culler.detect_colliding);
  EXPECT_EQ(a.culler.approximation.visible_pixels, b.culler.approximation.visible_pixels);
  EXPECT_EQ(a.culler.approximation.full_free_fraction, b.culler.approximation.full_free_fraction);
  EXPECT_EQ(a.culler.approximation.row_stride, b.culler.approximation.row_stride);
}

TEST(ConfigFile, WhatIsWrittenReadsBackAsWritten) {
  const CullerConfig c = unusual();
  expectSame(parseCullerConfig(formatCullerConfig(c)), c);
  CullerConfig all = c;
  all.culler.lookahead = kUnlimitedLookahead;
  all.culler.method = Method::LogState;
  all.culler.approximation.full_free_fraction = 0.25f;
  all.source = "a \"quoted\" name";
  expectSame(parseCullerConfig(formatCullerConfig(all)), all);
}

// What the config fuzzer found (tests/fuzz/corpus/config/finding_*): a fraction written
// with six digits read back as another float, and a source name with a control character
// (read from an escape such as \t) written as a space.
TEST(ConfigFile, EveryFractionAndSourceNameReadsBackExactly) {
  CullerConfig c = unusual();
  c.culler.method = Method::LogState;
  for (const float f : {0.1234567f, 0.1f, 1e-40f, std::nextafter(1.0f, 0.0f), -0.0f}) {
    c.culler.approximation.full_free_fraction = f;
    const CullerConfig back = parseCullerConfig(formatCullerConfig(c));
    EXPECT_EQ(std::memcmp(&back.culler.approximation.full_free_fraction, &f, sizeof f), 0)
        << f << " read back as " << back.culler.approximation.full_free_fraction;
  }
  for (const std::string& source :
       {std::string("tab\there"), std::string("new\nline\r\b\f"), std::string("nul\0x", 5),
        std::string("\x01\x1f\x7f\"\\/"), std::string("\xc3\xa9\xf0\x9f\x98\x80")}) {
    c.source = source;
    EXPECT_EQ(parseCullerConfig(formatCullerConfig(c)).source, source);
  }
}

// JSON's escapes read as JSON says (RFC 8259 §7), and only JSON numbers are numbers.
TEST(ConfigFile, StringsAndNumbersAreReadAsJson) {
  const auto withSource = [](const std::string& source) {
    return parseCullerConfig("{\"format\": \"logrid-config\", \"version\": 1, \"source\": \"" +
                             source + "\", \"culler\": {}}")
        .source;
  };
  EXPECT_EQ(withSource("p\\u0062o"), "pbo");
  EXPECT_EQ(withSource("\\u00e9\\/\\t"), "\xc3\xa9/\t");
  EXPECT_EQ(withSource("\\ud83d\\ude00"), "\xf0\x9f\x98\x80");  // a surrogate pair: one code point
  const auto refused = [](const std::string& text, const std::string& says) {
    SCOPED_TRACE(text);
    test::expectError([&] { parseCullerConfig(text, "c.json"); }, ErrorCode::BadInput, {says});
  };
  const std::string head = "{\"format\": \"logrid-config\", \"version\": 1, ";
  refused(head + "\"source\": \"\\x41\", \"culler\": {}}", "unknown escape");
  refused(head + "\"source\": \"\\u12g4\", \"culler\": {}}", "four hexadecimal digits");
  for (const char* number : {"nan", "NaN", "inf", "-Infinity", "0x10", "+16", ".5", "16.", "1e"}) {
    refused(head + "\"culler\": {\"tile_size\": " + number + "}}", "not a configuration file");
  }
  refused(head + "\"culler\": {\"tile_size\": 1e400}}", "beyond a double's range");
}

TEST(ConfigFile, AbsentKeysAreTheDescriptorsDefaultsAndUnknownKeysAreIgnored) {
  const CullerConfig c = parseCullerConfig(
      "{\"format\": \"logrid-config\", \"version\": 1, \"culler\": {\"method\": \"auto\"},"
      " \"scene\": {\"leaf\": 4}, \"report\": [1, {\"x\": null}]}");
  const CullerDesc defaults;
  EXPECT_EQ(c.culler.method, Method::Auto);
  EXPECT_EQ(c.culler.tile_size, defaults.tile_size);
  EXPECT_EQ(c.culler.lookahead, defaults.lookahead);
  EXPECT_EQ(c.culler.temporal_coherence, defaults.temporal_coherence);
  EXPECT_EQ(c.source, "");
}

void expectBad(const std::string& culler, const std::string& says) {
  const std::string text =
      "{\"format\": \"logrid-config\", \"version\": 1, \"culler\": " + culler + "}";
  try {
    parseCullerConfig(text, "c.json");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::BadInput);
    const std::string what = e.what();
    EXPECT_NE(what.find("c.json"), std::string::npos) << what;
    EXPECT_NE(what.find(says), std::string::npos) << what;
  }
}

TEST(ConfigFile, BadValuesAreRefusedNamingTheKey) {
  expectBad("{\"method\": \"fastest\"}", "method \"fastest\" is unknown");
  expectBad("{\"method\": 3}", "\"method\"");
  expectBad("{\"tile_size\": 0}", "tile");
  expectBad("{\"tile_size\": 16.5}", "\"tile_size\" is not a whole number");
  expectBad("{\"tile_size\": -16}", "\"tile_size\" is not a whole number");
  expectBad("{\"tile_size\": 1e300}", "\"tile_size\" is not a whole number");
  expectBad("{\"tile_size\": \"16\"}", "\"tile_size\" is not a whole number");
  expectBad("{\"lookahead\": 0}", "lookahead");
  expectBad("{\"lookahead\": \"many\"}", "\"lookahead\" is \"many\"");
  expectBad("{\"temporal_coherence\": 1}", "\"temporal_coherence\" is not true or false");
  expectBad("{\"approximation\": {\"full_free_fraction\": 2}}", "\"full_free_fraction\"");
  expectBad("{\"approximation\": {\"row_stride\": 0}}", "row stride 0");
  expectBad("{\"approximation\": 1}", "\"approximation\" is missing or not an object");
  expectBad("[]", "\"culler\" is missing or not an object");
}

TEST(ConfigFile, BadFilesAreRefusedWithTheReason) {
  const auto bad = [](const std::string& text, const std::string& says) {
    SCOPED_TRACE(text);
    test::expectError([&] { parseCullerConfig(text, "c.json"); }, ErrorCode::BadInput, {says});
  };
  bad("", "not a configuration file");
  bad("{\"format\": \"logrid-config\",", "not a configuration file");
  bad("[]", "one JSON object");
  bad("{\"format\": \"logrid-costs\", \"version\": 1, \"culler\": {}}", "\"format\"");
  bad("{\"format\": \"logrid-config\", \"version\": 2, \"culler\": {}}", "\"version\"");
  bad("{\"format\": \"logrid-config\", \"version\": 1}", "\"culler\"");
  bad("{\"format\": \"logrid-config\", \"version\": 1, \"source\": 1, \"culler\": {}}",
      "\"source\"");
  std::string deep;
  for (int i = 0; i < 40; ++i) deep += "[";
  bad(deep, "nested too deeply");
  bad("{\"format\": \"logrid-config\", \"version\": 1, \"culler\": {\"tile_size\": 8, "
      "\"tile_size\": 16}}",
      "the key \"tile_size\" twice");
}

TEST(ConfigFile, AnUnreadableFileSaysWhichAndHowToMakeOne) {
  try {
    loadCullerConfig("/nonexistent/config.json");
    ADD_FAILURE() << "a missing file was read";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Environment);
    const std::string what = e.what();
    EXPECT_NE(what.find("/nonexistent/config.json"), std::string::npos) << what;
    EXPECT_NE(what.find("tune --auto"), std::string::npos) << what;
  }
  const std::string path = testing::TempDir() + "logrid_config_test.json";
  {
    FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    const std::string text = formatCullerConfig(unusual());
    std::fwrite(text.data(), 1, text.size(), f);
    std::fclose(f);
  }
  expectSame(loadCullerConfig(path), unusual());
  std::remove(path.c_str());
}

}  // namespace
}  // namespace logrid
