// The puncturing planner's configuration (PuncturingMotionPlanner): the plan it verifies is read
// and checked at configure, and a bad plan or property is refused naming the component, the file,
// the line, the needle and what is wrong; with the plan from a navigation (plan_source), the
// verification waits for it and refuses a plan the navigation checks refuse. (Its walk of the whole procedure runs in the procedure
// tests: test/registration_sweep_test.cpp, test/procedure_test.cpp.)
#include "cobra/components/puncturing/procedure_planner.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "cobra/core/core.hpp"
#include "cobra/puncturing/plan.hpp"
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

TEST(PuncturingMotionPlanner, NavigatedTheVerificationWaitsForThePlanAndRefusesOneTheNavigationChecksRefuse) {
  using namespace std::chrono_literals;
  EXPECT_CONTAINS(configure([](core::Component& c) { c.setProperty("plan_source", std::string("dicom")); }).message,
                  "component 'NeedlePlanner': property plan_source is 'dicom'; expected files or navigation");
  PuncturingMotionPlanner planner("NeedlePlanner");
  planner.setProperty("scene_file", kApp + "deployment/puncturing.scene");
  planner.setProperty("preoperative_info_file", kScenario + "preoperative.txt");
  planner.setProperty("state_table_file", kApp + "state_table.txt");
  planner.setProperty("plan_source", std::string("navigation"));  // no cryo or probe plan file needed
  const core::Result configured = planner.configure();
  ASSERT_TRUE(configured) << configured.message;
  core::LockstepClock clock;
  clock.add(planner, 0ms);  // event-driven, as MotionPlanner runs: its requests and event ports wake it
  core::OutputPort<types::PointList> plan{"plan_out", "test navigation", "m"};
  core::OutputPort<KDL::Frame> abdomen{"abdomen", "test navigation", "m"};
  core::InputPort<std::string> refusal{"refusal_in", "test navigation", ""};
  core::InputPort<core::Event> events{"events_in", "test supervisor", ""};
  core::connectPorts(plan, planner.port("plan"));
  core::connectPorts(abdomen, planner.port("abdomenFrame"));
  core::connectPorts(planner.port("refusal"), refusal, core::ConnPolicy::buffer(4));
  core::connectPorts(planner.port("events"), events, core::ConnPolicy::buffer(16));
  const core::Result started = planner.start();
  ASSERT_TRUE(started) << started.message;
  const auto names = [&] {
    std::vector<std::string> all;
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) all.push_back(e.name.str());
    return all;
  };
  planner.call<void>("verifyProcedure");
  clock.advance(10ms);
  EXPECT_TRUE(names().empty()) << "waits for the plan and the registration";
  const puncturing::PuncturingPlan files = puncturing::loadPlan(
      kScenario + "preoperative.txt", kScenario + "cryo_plan.txt", kScenario + "us_plan.txt");
  types::PointList points;
  for (const puncturing::PlannedNeedle& n : files.needles) {
    points.add(n.name + ".entry", "plan", n.entry);
    points.add(n.name + ".target", "plan", n.target);
  }
  points.points[3].position = KDL::Vector(0.005, 0, -0.19);  // n2's target under the phantom
  plan.write(points);
  clock.advance(10ms);
  EXPECT_TRUE(names().empty()) << "waits for the registration";
  abdomen.write(files.preoperative.abdomen_in_task);
  clock.advance(10ms);
  EXPECT_EQ(names(), std::vector<std::string>{"e_procedure_refused"});
  const std::string why = "navigation refused: navigation plan:3: needle 'n2': target is 130.1 mm from the tumour "
                          "centre, outside its radius 12.0 mm";
  EXPECT_EQ(planner.call<std::string>("lastRefusal"), why);
  std::string line;
  ASSERT_EQ(refusal.read(line), core::FlowStatus::NewData);
  EXPECT_EQ(line, why);
  ASSERT_TRUE(planner.stop());
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
