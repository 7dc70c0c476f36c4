// What the viewer's panel and keys choose from (samples/viewer/settings.hpp) comes from
// logrid's tables, so methods and readers added there appear without a change.
#include "viewer/settings.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "cli/readers.hpp"
#include "expect_error.hpp"

namespace {

using logrid::viewer::CullSettings;

TEST(ViewSettingsTest, ChoicesAreTheTables) {
  const std::vector<std::string> methods = logrid::viewer::methodChoices();
  ASSERT_EQ(methods.size(), logrid::methodTable().size() + 1);
  for (const logrid::MethodInfo& m : logrid::methodTable()) {
    EXPECT_NE(std::find(methods.begin(), methods.end(), m.name), methods.end()) << m.name;
  }
  EXPECT_EQ(methods.back(), "oracle");
  EXPECT_EQ(logrid::viewer::readerChoices().size(), logrid::samples::readerTable().size());
  EXPECT_EQ(logrid::viewer::cycle(methods, methods.back(), 1), methods.front());
  EXPECT_EQ(logrid::viewer::cycle(methods, methods.front(), -1), methods.back());
}

TEST(ViewSettingsTest, ConfigurationCarriesEverySetting) {
  logrid::samples::RunConfig base;
  CullSettings s;
  s.method = "log-zfar";
  s.reader = "pbo";
  s.tile = 16;
  s.format = logrid::DepthFormat::D24;
  s.convention = logrid::DepthConvention::Reversed;
  s.lookahead = 8;
  s.coherence = true;
  s.approximation.row_stride = 2;
  s.verify = true;
  const logrid::samples::RunConfig c = logrid::viewer::configFor(base, s, 320, 200);
  EXPECT_EQ(c.view.width, 320u);
  EXPECT_EQ(c.view.height, 200u);
  EXPECT_EQ(c.view.depth.clip_range, logrid::ClipDepthRange::ZeroToOne);
  EXPECT_TRUE(c.overlay);
  EXPECT_TRUE(logrid::viewer::settingsOf(c) == s) << logrid::viewer::describe(s);
  s.method = "no-such-method";
  logrid::test::expectError([&] { logrid::viewer::configFor(base, s, 320, 200); },
                            logrid::ErrorCode::InvalidArgument, {"no-such-method", "oracle"});
  s.method = "log-state";
  s.tile = 0;
  logrid::test::expectError([&] { logrid::viewer::configFor(base, s, 320, 200); },
                            logrid::ErrorCode::InvalidArgument, {"tile"});
}

// Knobs a method does not take are left out (the panel shows them disabled), so that
// switching method never fails on them; switching back brings them back.
TEST(ViewSettingsTest, KnobsApplyOnlyWhereTheMethodTakesThem) {
  CullSettings s;
  s.approximation.visible_pixels = 10;
  s.approximation.full_free_fraction = 0.1f;
  s.approximation.row_stride = 2;
  for (const logrid::MethodInfo& m : logrid::methodTable()) {
    s.method = m.name;
    const logrid::samples::RunConfig c = logrid::viewer::configFor({}, s, 64, 64);
    const logrid::GridApproximation& a = c.culler.approximation;
    EXPECT_EQ(a.visible_pixels, m.takes.visible_pixels ? 10u : 0u) << m.name;
    EXPECT_EQ(a.full_free_fraction, m.takes.full_fraction ? 0.1f : 0.0f) << m.name;
    EXPECT_EQ(a.row_stride, m.takes.row_stride ? 2u : 1u) << m.name;
  }
  s.method = "vfc";
  EXPECT_NE(logrid::viewer::describe(s).find("exact"), std::string::npos);
}

TEST(ViewSettingsTest, ShadeFollowsTheMethodsSemantics) {
  using logrid::samples::TileShade;
  using logrid::viewer::ShadeChoice;
  for (const logrid::MethodInfo& m : logrid::methodTable()) {
    EXPECT_EQ(
        logrid::viewer::shadeFor(ShadeChoice::Auto, m.name),
        m.semantics == logrid::TestSemantics::OcclusionState ? TileShade::States : TileShade::Zfar)
        << m.name;
  }
  EXPECT_EQ(logrid::viewer::shadeFor(ShadeChoice::Zfar, "log-state"), TileShade::Zfar);
}

}  // namespace
