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

// A path in a plane (x and y both positions) with labelled points, e.g. where each phase of a task
// began (the thesis' Fig. 6.7): every marker drawn, each label beside its marker, in the series' colour.
TEST(SvgPlot, DrawsLabelledMarkersBesideTheirPoints) {
  Series path{"actual", {0, 0.1, 0.2}, {0.1, 0.115, 0.1}};
  path.marker_x = {0, 0.1, 0.3};  // the last one outside the line: the axes include it
  path.marker_y = {0.1, 0.115, 0.1};
  path.marker_labels = {"A", "B<"};
  Figure f{"", {{"y-z", "y [m]", "z [m]", {{"nominal", {0, 0.2}, {0.1, 0.1}, true}, path}}}};
  const std::string svg = toSvg(f);
  std::size_t circles = 0;
  for (auto at = svg.find("<circle"); at != std::string::npos; at = svg.find("<circle", at + 1)) ++circles;
  EXPECT_EQ(circles, 3U);
  EXPECT_CONTAINS(svg, "font-weight='bold' fill='#D55E00'>A</text>");
  EXPECT_CONTAINS(svg, ">B&lt;</text>");
  EXPECT_CONTAINS(svg, ">0.3</text>");  // an x tick at the third marker
  // A label sits 5 px right of and 6 px above its marker.
  const auto circle = svg.find("<circle cx='");
  const double cx = std::stod(svg.substr(circle + 12));
  const auto label = svg.find("<text x='", circle);
  EXPECT_DOUBLE_EQ(std::stod(svg.substr(label + 9)), cx + 5);
}

TEST(SvgPlot, RefusesMarkersThatDoNotPair) {
  Series s{"path", {0, 1}, {0, 1}};
  s.marker_x = {0, 1};
  s.marker_y = {0};
  Figure f{"", {{"p", "x", "y", {s}}}};
  EXPECT_EQ(cobra::test_support::messageOf([&] { toSvg(f); }),
            "plot: panel 'p', series 'path' has 2 marker x, 1 marker y and 0 marker labels; give as many x as y and "
            "at most one label per marker");
  f.panels[0].series[0].marker_y = {0, 1};
  f.panels[0].series[0].marker_labels = {"A", "B", "C"};
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { toSvg(f); }), "2 marker x, 2 marker y and 3 marker labels");
  f.panels[0].series[0].marker_labels = {"A"};
  f.panels[0].series[0].marker_y = {0, INFINITY};
  EXPECT_EQ(cobra::test_support::messageOf([&] { toSvg(f); }), "plot: panel 'p', series 'path': marker 1 is not finite");
}

}  // namespace
}  // namespace cobra::plot
