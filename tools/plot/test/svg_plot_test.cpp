#include "cobra/plot/svg_plot.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "cobra/test_support/test_support.hpp"

namespace cobra::plot {
namespace {

TEST(SvgPlot, TicksAreNiceAndCoverTheRange) {
  EXPECT_EQ(niceTicks(0.0, 1.0, 5), (std::vector<double>{0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0}));
  const auto ticks = niceTicks(-3.2, 7.9, 6);
  ASSERT_FALSE(ticks.empty());
  EXPECT_GE(ticks.front(), -3.2);
  EXPECT_LE(ticks.back(), 7.9);
  EXPECT_DOUBLE_EQ(ticks[1] - ticks[0], 2.0);
  EXPECT_TRUE(niceTicks(1.0, 1.0).empty());
}

TEST(SvgPlot, DrawsEverySeriesWithItsLegendAndEscapesText) {
  Figure f{"q(t) <axes>", {{"position", "t [s]", "q [m]", {{"x", {0, 1, 2}, {0, 1, 0}}, {"y & z", {0, 2}, {1, 1}, true}}}}};
  const std::string svg = toSvg(f);
  EXPECT_CONTAINS(svg, "<svg xmlns='http://www.w3.org/2000/svg'");
  EXPECT_CONTAINS(svg, "q(t) &lt;axes&gt;");
  EXPECT_CONTAINS(svg, ">y &amp; z</text>");
  EXPECT_CONTAINS(svg, "stroke-dasharray='6,4'");
  std::size_t lines = 0;
  for (auto at = svg.find("<polyline"); at != std::string::npos; at = svg.find("<polyline", at + 1)) ++lines;
  EXPECT_EQ(lines, 2U);
}

TEST(SvgPlot, RefusesSeriesThatCannotBeDrawn) {
  Figure f{"", {{"p", "t", "q", {{"bad", {0, 1}, {0}}}}}};
  EXPECT_EQ(cobra::test_support::messageOf([&] { toSvg(f); }),
            "plot: panel 'p', series 'bad' has 2 x and 1 y values; give as many of each");
  f.panels[0].series[0].y = {0, std::nan("")};
  EXPECT_EQ(cobra::test_support::messageOf([&] { toSvg(f); }), "plot: panel 'p', series 'bad': point 1 is not finite");
}

}  // namespace
}  // namespace cobra::plot
