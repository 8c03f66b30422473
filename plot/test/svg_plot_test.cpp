#include "cobra/plot/svg_plot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

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

std::size_t countOf(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Every <text> element's text with its x and anchor (the layout's own).
struct TextAt {
  double x;
  std::string anchor, text, font;
  bool bold;
};
std::vector<TextAt> textsOf(const std::string& svg) {
  std::vector<TextAt> out;
  for (auto at = svg.find("<text "); at != std::string::npos; at = svg.find("<text ", at + 1)) {
    const auto close = svg.find('>', at), end = svg.find("</text>", close);
    const std::string tag = svg.substr(at, close - at);
    auto attribute = [&](const std::string& name) {
      const auto a = tag.find(" " + name + "='");
      return a == std::string::npos ? std::string() : tag.substr(a + name.size() + 3, tag.find('\'', a + name.size() + 3) - a - name.size() - 3);
    };
    if (tag.find("x='") == std::string::npos || tag.find("transform") != std::string::npos) continue;
    out.push_back({std::stod(attribute("x")), attribute("text-anchor"), svg.substr(close + 1, end - close - 1),
                   attribute("font-size"), attribute("font-weight") == "bold"});
  }
  return out;
}

// A single-panel figure whose panel repeats the figure's title shows it once.
TEST(SvgPlot, DrawsATitleThatThePanelRepeatsOnce) {
  Figure f{"Energy tanks", {{"Energy tanks", "t [s]", "[J]", {{"a", {0, 1}, {0, 1}}}}}};
  EXPECT_EQ(countOf(toSvg(f), "Energy tanks"), 1U);
  f.panels[0].title = "needle";
  EXPECT_EQ(countOf(toSvg(f), "Energy tanks"), 1U);
  EXPECT_EQ(countOf(toSvg(f), ">needle</text>"), 1U);
}

// Long titles wrap and long legend labels are shortened in their middle: every text of the figure
// ends inside its width, whatever the names.
TEST(SvgPlot, KeepsTitlesAndLegendsWithinTheFigure) {
  const std::string port = "Patient.needleAxialForceMeasuredAlongTheShaftInTheTissueFrameOfThePhantom.value";
  Figure f{"Tool tracking error, I-SUR needle (commanded NeedleAdmittance.admPose, measured ISUR.measCartPose)",
           {{"position error of the needle tip while the needle deployment is autonomous planning or primitives",
             "t [s]", "[mm]", {}}},
           600};
  for (int k = 0; k < 6; ++k) f.panels[0].series.push_back({port + std::to_string(k), {0, 1}, {0, double(k)}});
  const std::string svg = toSvg(f);
  bool shortened = false;
  for (const TextAt& t : textsOf(svg)) {
    const double font = std::stod(t.font.empty() ? "11" : t.font);
    const double w = textWidth(t.text, font, t.bold);
    const double right = t.anchor == "middle" ? t.x + w / 2 : (t.anchor == "end" ? t.x : t.x + w);
    EXPECT_LE(right, 600.0) << t.text;
    EXPECT_GE(t.anchor == "middle" ? t.x - w / 2 : t.x, 0.0) << t.text;
    shortened = shortened || t.text.find("\xE2\x80\xA6") != std::string::npos;
  }
  EXPECT_TRUE(shortened) << "the port names are wider than the figure";
  EXPECT_CONTAINS(svg, ">Tool tracking error, I-SUR needle (commanded</text>");
  EXPECT_CONTAINS(svg, ">Patient.needle");  // the head of a shortened label
  EXPECT_CONTAINS(svg, "Phantom.value5</text>");  // and its tail, which tells the series apart
}

TEST(SvgPlot, FitsAndWrapsTextByItsMeasuredWidth) {
  EXPECT_EQ(fitText("short", 12, 100), "short");
  const std::string fitted = fitText("NeedleAdmittance.admPose.z", 12, 120);
  EXPECT_LE(textWidth(fitted, 12), 120);
  EXPECT_EQ(fitted.substr(0, 6), "Needle");
  EXPECT_EQ(fitted.back(), 'z');
  EXPECT_GT(textWidth("WWW", 12), textWidth("iii", 12));
  EXPECT_DOUBLE_EQ(textWidth("a", 20), 2 * textWidth("a", 10));
  EXPECT_EQ(wrapText("one two three", 12, textWidth("one two", 12)), (std::vector<std::string>{"one two", "three"}));
}

// Series that coincide stay visible: each has its own dash pattern and its own marker shape, the
// markers staggered along the line.
TEST(SvgPlot, GivesCoincidingSeriesDistinctDashesAndMarkers) {
  Series line{"commanded", {}, {}};
  for (int i = 0; i < 50; ++i) line.x.push_back(0.1 * i), line.y.push_back(std::sin(0.1 * i));
  Series same = line;
  same.label = "measured";
  Figure f{"", {{"p", "t [s]", "z [m]", {line, same}}}};
  const std::string svg = toSvg(f);
  EXPECT_EQ(countOf(svg, "<polyline fill='none' stroke='#0072B2' stroke-width='1.6' points="), 1U) << "solid";
  EXPECT_EQ(countOf(svg, "<polyline fill='none' stroke='#D55E00' stroke-width='1.6' stroke-dasharray='8,3'"), 1U);
  const std::size_t circles = countOf(svg, "d='M") - countOf(svg, "h6.4v6.4h-6.4z");
  const std::size_t squares = countOf(svg, "h6.4v6.4h-6.4z");
  EXPECT_EQ(circles, squares) << "as many markers of each, the legend's one included";
  EXPECT_GE(squares, 2U);
  // Beside a dashed reference, the first other series is solid.
  Figure paths{"", {{"y-z", "y [m]", "z [m]", {{"nominal", {0, 1}, {0, 0}, true}, {"actual", {0, 1}, {0, 0.1}}}}}};
  const std::string drawn = toSvg(paths);
  EXPECT_EQ(countOf(drawn, "<polyline fill='none' stroke='#D55E00' stroke-width='1.6' points="), 1U) << drawn;
  // The first marker of each series at a different point of the (same) line.
  const auto first = svg.find("class='marker' d='M"), second = svg.find("h6.4v6.4h-6.4z");
  EXPECT_NE(std::stod(svg.substr(first + 19)) + 3.6, std::stod(svg.substr(svg.rfind("d='M", second) + 4)) + 3.2);
}

// x and y both lengths (a path in a plane): a metre takes as many pixels on either axis.
TEST(SvgPlot, DrawsAPathOfLengthsWithEqualAxes) {
  Figure f{"", {{"path", "y [m]", "z [m]", {{"path", {0, 1}, {0, 0.1}, true}}}}};
  auto slope = [&](const Figure& figure) {  // pixels of y per pixel of x along the line
    const std::string svg = toSvg(figure);
    std::istringstream points(svg.substr(svg.find("points='") + 8));
    double x0, y0, x1, y1;
    char comma;
    points >> x0 >> comma >> y0 >> x1 >> comma >> y1;
    return (y0 - y1) / (x1 - x0);
  };
  EXPECT_TRUE(equalAxes(f.panels[0]));
  EXPECT_NEAR(slope(f), 0.1, 1e-3);
  f.panels[0].x_label = "t [s]";
  EXPECT_FALSE(equalAxes(f.panels[0]));
  EXPECT_GT(slope(f), 0.2) << "free axes stretch the 0.1 m rise over the panel's height";
  f.panels[0].aspect = Aspect::Equal;
  EXPECT_NEAR(slope(f), 0.1, 1e-3);
  double xl = 0, xh = 2, yl = 0, yh = 0.5;
  equalise(xl, xh, yl, yh, 400, 200);
  EXPECT_DOUBLE_EQ((xh - xl) / 400, (yh - yl) / 200);
  EXPECT_DOUBLE_EQ(xl, 0.0);
  EXPECT_DOUBLE_EQ((yl + yh) / 2, 0.25) << "widened about its centre";
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
