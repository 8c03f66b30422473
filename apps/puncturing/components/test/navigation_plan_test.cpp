// The navigated plan (navigation_plan.hpp): the two_needles plan sent as points equals the one
// its files give (probe poses included, by probePlan), and every refusal names what is wrong.
#include "cobra/components/puncturing/navigation_plan.hpp"

#include <gtest/gtest.h>

#include <string>

#include "cobra/puncturing/plan.hpp"

namespace cobra::components {
namespace {

namespace pp = cobra::puncturing;
namespace nav = cobra::components::puncturing_navigation;

const std::string kScenario = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/scenarios/two_needles/";

struct Fixture {
  pp::PuncturingPlan files =
      pp::loadPlan(kScenario + "preoperative.txt", kScenario + "cryo_plan.txt", kScenario + "us_plan.txt");
  types::PointList points;
  KDL::Frame registration = files.preoperative.abdomen_in_task;
  Fixture() {
    for (const pp::PlannedNeedle& n : files.needles) {
      points.add(n.name + ".entry", "plan", n.entry);
      points.add(n.name + ".target", "plan", n.target);
    }
  }
  std::string build(pp::PuncturingPlan& plan) const {
    return nav::buildPlan(points, registration, files.preoperative, plan);
  }
  std::string refusal() const {
    pp::PuncturingPlan plan;
    return build(plan);
  }
};

TEST(NavigationPlan, TheFilesPlanSentAsPointsGivesTheSameNeedlesAndProbePoses) {
  Fixture f;
  pp::PuncturingPlan plan;
  ASSERT_EQ(f.build(plan), "");
  ASSERT_EQ(plan.needles.size(), f.files.needles.size());
  for (std::size_t i = 0; i < plan.needles.size(); ++i) {
    EXPECT_EQ(plan.needles[i].name, f.files.needles[i].name);
    EXPECT_TRUE(KDL::Equal(plan.needles[i].entry, f.files.needles[i].entry, 1e-12));
    EXPECT_TRUE(KDL::Equal(plan.needles[i].target, f.files.needles[i].target, 1e-12));
    EXPECT_EQ(plan.needles[i].line, static_cast<int>(2 * i + 1)) << "the needle's first point";
    // us_plan.txt is written by tools/probe_plan.py with 6 decimals (m).
    EXPECT_TRUE(KDL::Equal(plan.probes[i].pose, f.files.probes[i].pose, 1e-5)) << i;
  }
  EXPECT_TRUE(KDL::Equal(plan.preoperative.abdomen_in_task, f.registration, 1e-15));
  EXPECT_EQ(nav::describe(plan),
            "registration (0.0, 0.0, 100.0 mm; 0.00, 0.00, 0.00 deg), plan of 2 needles: n1 entry (-20.0, -6.0, 0.0 mm) "
            "target (-5.0, 0.0, -58.0 mm) n2 entry (-10.0, 8.0, 0.0 mm) target (5.0, 0.0, -62.0 mm)");
}

TEST(NavigationPlan, ARegistrationWithinTheToleranceIsTheOneTaken) {
  Fixture f;
  f.registration = KDL::Frame(KDL::Rotation::RotZ(0.01), f.registration.p + KDL::Vector(0.0015, 0, 0));
  pp::PuncturingPlan plan;
  ASSERT_EQ(f.build(plan), "");
  EXPECT_TRUE(KDL::Equal(plan.preoperative.abdomen_in_task, f.registration, 1e-15));
}

TEST(NavigationPlan, RefusesNamingThePointTheNeedleAndWhy) {
  {
    Fixture f;
    f.points.points[2].name.assign("n2.tip");
    EXPECT_EQ(f.refusal(), "navigation plan:3: point 'n2.tip': expected a name NEEDLE.entry or NEEDLE.target");
  }
  {
    Fixture f;
    f.points.points[3].name.assign("n2.entry");
    EXPECT_EQ(f.refusal(), "navigation plan:4: point 'n2.entry' comes twice");
  }
  {
    Fixture f;
    f.points.count = 3;  // n2 without its target
    EXPECT_EQ(f.refusal(), "navigation plan:3: needle 'n2': no target point (n2.target)");
  }
  {
    Fixture f;
    f.points.count = 0;
    EXPECT_EQ(f.refusal(), "navigation plan: no points; expected NEEDLE.entry and NEEDLE.target of each needle");
  }
  {
    Fixture f;
    f.points.points[3].position = KDL::Vector(0.005, 0, -0.19);  // 10 cm under the phantom
    EXPECT_EQ(f.refusal(),
              "navigation plan:3: needle 'n2': target is 130.1 mm from the tumour centre, outside its radius 12.0 mm");
  }
}

TEST(NavigationPlan, ARegistrationBeyondTheToleranceIsRefusedSayingHowFar) {
  Fixture f;
  f.registration.p += KDL::Vector(0, 0.003, 0);
  EXPECT_EQ(f.refusal(), "registration: frame A lies 3.0 mm and 0.00 deg from the preoperative abdomen the planning "
                         "scene, the monitors and the patient were set up with; at most 2.0 mm and 1.00 deg can be taken");
  Fixture turned;
  turned.registration.M = KDL::Rotation::RotZ(0.02);
  EXPECT_EQ(turned.refusal(), "registration: frame A lies 0.0 mm and 1.15 deg from the preoperative abdomen the "
                              "planning scene, the monitors and the patient were set up with; at most 2.0 mm and "
                              "1.00 deg can be taken");
}

}  // namespace
}  // namespace cobra::components
