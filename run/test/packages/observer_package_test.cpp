// An observer added by a package (observer.hpp: ObserverRegistry::add from cobra_register_package):
// the package cobra_time_in_state (time_in_state.cpp, built as an out-of-tree package is) is
// loaded by the application's packages_list, and its section `time_in_state` of the `run` table
// puts the time spent in each task state into the run's summary and report. Its section's field
// errors and an unknown section name the file:line.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "cobra/run/observer.hpp"
#include "cobra/run/runner.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::run {
namespace {

using test_support::messageOf;

const std::filesystem::path kHere = std::filesystem::path(COBRA_SOURCE_DIR) / "run/test/packages";

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

class ObserverPackage : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("COBRA_PACKAGE_PATH", COBRA_PACKAGE_DIR, 1); }
  void TearDown() override { std::filesystem::remove_all(scratch_); }

  /// The app with its run table's `time_in_state = { chart = "task" },` line replaced by `line`,
  /// written into this test's scratch folder.
  std::filesystem::path appWith(const std::string& line) {
    std::string text = readFile(kHere / "time_in_state_app.lua");
    const std::string original = "  time_in_state = { chart = \"task\" },";
    text.replace(text.find(original), original.size(), line);
    text.replace(text.find("here .. \"../apps"), 16, "\"" + (kHere / "../apps").string());
    std::filesystem::create_directories(scratch_);
    const auto path = scratch_ / "time_in_state_app.lua";
    std::ofstream(path) << text;
    return path;
  }
  /// This test's own folder (removed after it): its app variant and its report.
  const std::filesystem::path scratch_ =
      test_support::scratchPath(std::string("time_in_state_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());

  static RunOptions options(const std::filesystem::path& app) {
    RunOptions o;
    o.app = app;
    o.time_limit = 5.0;
    return o;
  }
};

TEST_F(ObserverPackage, APackagesTimeInStateObserverPutsEachStatesTimeIntoTheSummaryAndTheReport) {
  RunOptions o = options(kHere / "time_in_state_app.lua");
  o.report_folder = scratch_ / "report";
  const RunResult r = runApp(o);
  ASSERT_TRUE(r.completed()) << r.reason;
  const ObserverRegistry::Kind* kind = ObserverRegistry::find("time_in_state");
  ASSERT_NE(kind, nullptr);
  EXPECT_EQ(kind->owner, "package 'cobra_time_in_state'");
  // The task waits until the sine passes 0.9 (0.18 s), is high until it falls under 0.85
  // (about 0.33 s), then done; the chart steps every 10 ms.
  const SummaryValue& time = r.value("time in state, task");
  EXPECT_EQ(time.unit, "s");
  ASSERT_EQ(time.values.size(), 3u) << time.text;
  EXPECT_NEAR(time.values[0], 0.18, 0.011);
  EXPECT_NEAR(time.values[1], 0.15, 0.02);
  EXPECT_NEAR(time.values[0] + time.values[1] + time.values[2], r.duration, 1e-9);
  EXPECT_TRUE(std::regex_search(time.text, std::regex("^root.waiting 0.1[0-9]{2} s, root.high 0.1[0-9]{2} s, root.done 0.0[0-9]{2} s$")))
      << time.text;
  EXPECT_EQ(r.value("threshold crossings").text, "1");  // cobra's own summary beside it
  const std::string html = readFile(o.report_folder / "report.html");
  EXPECT_NE(html.find("<th>time in state, task</th><td>root.waiting "), std::string::npos);
}

TEST_F(ObserverPackage, AnUnknownFieldOfItsSectionNamesTheFileLineAndTheKnownFields) {
  const auto app = appWith("  time_in_state = { chrat = \"task\" },");
  EXPECT_EQ(messageOf([&] { (void)runApp(options(app)); }),
            app.string() + ":12: run.time_in_state: unknown field 'chrat'; did you mean 'chart'? known fields: chart");
}

TEST_F(ObserverPackage, AnUnknownChartIsRefusedAtAttach) {
  const auto app = appWith("  time_in_state = { chart = \"tsak\" },");
  EXPECT_EQ(messageOf([&] { (void)runApp(options(app)); }), app.string() + ":12: run.time_in_state: unknown chart 'tsak'");
}

TEST_F(ObserverPackage, ASectionNoObserverIsRegisteredForIsRefusedWithTheKnownNames) {
  const auto app = appWith("  time_in_stat = { chart = \"task\" },");
  const std::string message = messageOf([&] { (void)runApp(options(app)); });
  EXPECT_EQ(message.rfind(app.string() + ":12: run.time_in_stat: unknown section 'time_in_stat'", 0), 0u) << message;
  EXPECT_NE(message.find("did you mean 'time_in_state'?"), std::string::npos) << message;
  EXPECT_NE(message.find("known sections: "), std::string::npos) << message;
}

}  // namespace
}  // namespace cobra::run
