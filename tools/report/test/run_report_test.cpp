// The run report: event log CSV, state timeline, HTML page, run folder.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "cobra/report/run_report.hpp"
#include "cobra/test_support/test_support.hpp"

using namespace cobra::report;
using ::testing::HasSubstr;
using ::testing::Not;

TEST(TimelineRecorder, OnlyChangesStartIntervalsAndOpenOnesCloseAtTheEnd) {
  TimelineRecorder timeline;
  timeline.observe(0.0, "needle", "root.WaitIceballConfig");
  timeline.observe(0.5, "probe", "root.MoveToSkin");
  timeline.observe(1.0, "needle", "root.WaitIceballConfig");
  timeline.observe(2.0, "needle", "root.InsertingNeedles.MoveToSkin");
  timeline.observe(3.0, "needle", "root.WaitIceballConfig");
  const auto intervals = timeline.intervals(4.0);
  ASSERT_EQ(intervals.size(), 4u);
  EXPECT_EQ(intervals[0].state, "root.WaitIceballConfig");
  EXPECT_DOUBLE_EQ(intervals[0].end, 2.0);
  EXPECT_EQ(intervals[1].chart, "probe");
  EXPECT_DOUBLE_EQ(intervals[1].end, 4.0) << "the open interval closes at the end time";
  EXPECT_EQ(intervals[2].state, "root.InsertingNeedles.MoveToSkin");
  EXPECT_DOUBLE_EQ(intervals[3].begin, 3.0);
  EXPECT_EQ(timeline.statesEntered("needle"),
            (std::vector<std::string>{"root.WaitIceballConfig", "root.InsertingNeedles.MoveToSkin"}));
  EXPECT_TRUE(timeline.statesEntered("nobody").empty());
}

TEST(TimelineRecorder, RefusesTimeGoingBackwards) {
  TimelineRecorder timeline;
  timeline.observe(2.0, "needle", "a");
  try {
    timeline.observe(1.0, "needle", "b");
    FAIL() << "time went backwards";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("timeline of chart 'needle': time 1 s is before 2 s"));
  }
}

TEST(EventLog, IsCsvWithQuotedFieldsWhenNeeded) {
  const std::string csv = eventLogCsv({{0.25, "NeedleSup", "e_skin_touched", "root.PenetratingSkin"},
                                       {1.5, "Surgeon", "say \"recover\", now", ""}});
  std::istringstream lines(csv);
  std::string header, first, second;
  std::getline(lines, header);
  std::getline(lines, first);
  std::getline(lines, second);
  EXPECT_EQ(header, "time [s],source,event,state");
  EXPECT_EQ(first, "0.25,NeedleSup,e_skin_touched,root.PenetratingSkin");
  EXPECT_EQ(second, "1.5,Surgeon,\"say \"\"recover\"\", now\",");
}

TEST(TimelineSvg, DrawsOneLanePerChartAndLabelsBoxesThatFit) {
  const std::string svg = timelineSvg({{"needle", "root.Long.MoveToTumor", 0.0, 9.0},
                                       {"needle", "root.Tiny", 9.0, 9.001},
                                       {"probe", "root.USPositioned", 0.0, 10.0}});
  EXPECT_THAT(svg, HasSubstr(">needle</text>"));
  EXPECT_THAT(svg, HasSubstr(">probe</text>"));
  EXPECT_THAT(svg, HasSubstr(">MoveToTumor</text>")) << "the leaf name labels a wide box";
  EXPECT_THAT(svg, HasSubstr("<title>root.Tiny: 9 s to 9.001 s</title>")) << "a narrow box keeps its tooltip";
  const auto tiny = svg.find("<title>root.Tiny");
  EXPECT_THAT(svg.substr(tiny, svg.find("</g>", tiny) - tiny), Not(HasSubstr("<text")))
      << "but no label that would overflow it";
}

// The timeline's legend names every state of every lane beside its colour, and a lane's states
// take distinct colours (a state's box and its swatch the same).
TEST(TimelineSvg, HasALegendOfEachLanesStatesInTheirColours) {
  const std::string svg = timelineSvg({{"needle", "root.A", 0.0, 1.0},
                                       {"needle", "root.B.Tiny", 1.0, 1.001},
                                       {"needle", "root.C", 1.001, 3.0},
                                       {"probe configuration", "probe_contact", 0.0, 3.0}});
  auto swatch = [&](const std::string& state) {
    const auto label = svg.find(">" + state + "</text>", svg.find("class=\"swatch\""));
    EXPECT_NE(label, std::string::npos) << state << " is in the legend";
    const auto fill = svg.rfind("fill=\"", label);
    return svg.substr(fill + 6, 7);
  };
  EXPECT_EQ(swatch("Tiny"), "#D55E00") << "the second state of the lane";
  EXPECT_NE(swatch("A"), swatch("C"));
  EXPECT_EQ(swatch("probe_contact"), "#0072B2") << "each lane's states take the colours from the first";
  EXPECT_THAT(svg, HasSubstr("<title>root.B.Tiny: 1 s to 1.001 s</title><rect x=\"393.333\" y=\"4\" width=\"1\" "
                             "height=\"26\" fill=\"#D55E00\""));
}

// A figure's title is the heading of its section: the page shows it once, not again in the SVG or
// as the title of a panel that repeats it; a panel with its own title keeps it.
TEST(RunReportHtml, ShowsEachFigureTitleOnce) {
  RunReport report;
  report.title = "run";
  report.figures = {{"Needle force", {{"Needle force", "depth [m]", "force [N]", {{"fz", {0.0, 0.01}, {0.0, 1.5}}}}}},
                    {"Tracking", {{"position error", "t [s]", "[mm]", {{"e", {0.0, 1.0}, {0.0, 0.5}}}}}}};
  const std::string html = toHtml(report);
  auto count = [&](const std::string& text) {
    std::size_t n = 0;
    for (auto at = html.find(text); at != std::string::npos; at = html.find(text, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("Needle force"), 1U);
  EXPECT_THAT(html, HasSubstr("<h2>Needle force</h2>"));
  EXPECT_EQ(count("Tracking"), 1U);
  EXPECT_EQ(count(">position error</text>"), 1U);
}

TEST(RunFolder, HoldsTheEventLogAndASelfContainedPage) {
  const auto folder = ::cobra::test_support::scratchPath("cobra_run_report_test");
  std::filesystem::remove_all(folder);
  RunReport report;
  report.title = "Puncturing <demo>";
  report.summary = {{"needles placed", "2 of 2"}, {"placement error", "0.8 mm, 1.1 mm"}};
  report.events = {{0.1, "Surgeon", "e_needle_mounted", "root.MoveToSkin"}};
  report.timeline = {{"needle", "root.MoveToSkin", 0.0, 1.0}};
  report.figures = {{"Needle force", {{"force vs depth", "depth [m]", "force [N]", {{"fz", {0.0, 0.01}, {0.0, 1.5}}}}}}};
  report.files = {"signals.csv"};
  const auto page = writeRunFolder(folder, report);
  EXPECT_EQ(page, folder / "report.html");
  std::ifstream in(page);
  const std::string html((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_THAT(html, HasSubstr("<title>Puncturing &lt;demo&gt;</title>"));
  EXPECT_THAT(html, HasSubstr("<th>placement error</th><td>0.8 mm, 1.1 mm</td>"));
  EXPECT_THAT(html, HasSubstr("<h2>Needle force</h2>"));
  EXPECT_THAT(html, HasSubstr("<a href=\"signals.csv\">signals.csv</a>"));
  EXPECT_THAT(html, HasSubstr("<td>e_needle_mounted</td>"));
  EXPECT_THAT(html, HasSubstr("<td>root.<wbr>MoveToSkin</td>")) << "a long state path wraps at its dots";
  EXPECT_THAT(html, Not(HasSubstr("<script"))) << "self-contained, nothing to run or download";
  EXPECT_TRUE(std::filesystem::exists(folder / "events.csv"));
  std::filesystem::remove_all(folder);
}

TEST(RunFolder, NamesTheFolderItCannotCreate) {
  try {
    writeRunFolder("/proc/cobra/not/here", RunReport{});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("run report: cannot create folder /proc/cobra/not/here"));
  }
}
