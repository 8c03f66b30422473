// The puncturing planner's configuration (PuncturingMotionPlanner): the plan it verifies is read
// and checked at configure, and a bad plan or property is refused naming the component, the file,
// the line, the needle and what is wrong. (Its walk of the whole procedure runs in the procedure
// tests: test/registration_sweep_test.cpp, test/procedure_test.cpp.)
#include "cobra/components/puncturing/procedure_planner.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "cobra/core/core.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

const std::string kApp = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/";
const std::string kScenario = kApp + "scenarios/two_needles/";

/// configure() of a needle planner on the app's scene and two_needles, after `set`.
core::Result configure(const std::function<void(core::Component&)>& set) {
  PuncturingMotionPlanner planner("NeedlePlanner");
  planner.setProperty("scene_file", kApp + "deployment/puncturing.scene");
  planner.setProperty("preoperative_info_file", kScenario + "preoperative.txt");
  planner.setProperty("cryo_plan_file", kScenario + "cryo_plan.txt");
  planner.setProperty("US_pose_plan_file", kScenario + "us_plan.txt");
  planner.setProperty("state_table_file", kApp + "state_table.txt");
  set(planner);
  return planner.configure();
}

TEST(PuncturingMotionPlanner, ConfiguresWithTheAppsPlanAndTable) {
  const core::Result result = configure([](core::Component&) {});
  EXPECT_TRUE(result) << result.message;
}

TEST(PuncturingMotionPlanner, APlanWhoseTargetLeavesTheTumourIsRefusedNamingTheNeedle) {
  // n2's target 3 cm deeper: outside the tumour (and below the phantom's tissue it is planned in).
  const std::filesystem::path bad = std::filesystem::temp_directory_path() / "cobra_procedure_planner_cryo_plan.txt";
  std::ifstream in(kScenario + "cryo_plan.txt");
  std::ofstream out(bad);
  int line_number = 0, n2_line = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    if (line.rfind("needle n2 ", 0) == 0) {
      const std::size_t at = line.find("target=");
      const std::size_t z = line.find(',', line.find(',', at) + 1) + 1;
      const std::size_t end = line.find_first_of(" \t", z);
      const double deeper = std::stod(line.substr(z, end - z)) - 0.03;
      line = line.substr(0, z) + std::to_string(deeper) + (end == std::string::npos ? "" : line.substr(end));
      n2_line = line_number;
    }
    out << line << "\n";
  }
  out.close();
  ASSERT_GT(n2_line, 0) << "two_needles' cryo_plan.txt has no needle n2";
  const core::Result result = configure([&](core::Component& c) { c.setProperty("cryo_plan_file", bad.string()); });
  EXPECT_FALSE(result);
  EXPECT_CONTAINS(result.message, "component 'NeedlePlanner': " + bad.string() + ":" + std::to_string(n2_line) +
                                      ": needle 'n2': target is ");
  EXPECT_CONTAINS(result.message, "from the tumour centre, outside its radius");
}

TEST(PuncturingMotionPlanner, BadPropertiesAreRefusedNamingThem) {
  EXPECT_CONTAINS(configure([](core::Component& c) { c.setProperty("arm", std::string("scalpel")); }).message,
                  "component 'NeedlePlanner': property arm is 'scalpel'; expected needle or probe");
  EXPECT_CONTAINS(configure([](core::Component& c) { c.setProperty("state_table_file", std::string()); }).message,
                  "component 'NeedlePlanner': property state_table_file is empty; give the path of its file");
}

TEST(PuncturingMotionPlanner, ASceneWithoutTheProceduresRobotsIsRefusedNamingTheFileAndTheExpectedRobots) {
  // The suturing scene: the I-SUR alone.
  const std::string scene = std::string(COBRA_SOURCE_DIR) + "/apps/suturing/deployment/suturing.scene";
  const core::Result result = configure([&](core::Component& c) { c.setProperty("scene_file", scene); });
  EXPECT_FALSE(result);
  EXPECT_CONTAINS(result.message, "component 'NeedlePlanner': scene_file '" + scene +
                                      "' has no robot 'ur5'; the procedure's verification expects the needle robot "
                                      "'isur' and the probe robot 'ur5'");
}

}  // namespace
}  // namespace cobra::components
