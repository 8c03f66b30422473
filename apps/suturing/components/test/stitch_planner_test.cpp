// StitchPlanner (component) fed by WoundSimulator's edges on the lockstep clock: the planned
// targets are the simulated wound's stitch points in the world; the plan follows the wound (the
// second stitch is planned narrower once the first is pulled closed); four stitches then
// e_stitches_done; no edges -> e_no_wound_data; bad properties refused; answering allocates nothing.
#include "cobra/components/suturing/stitch_planner.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cobra/components/sim/wound_simulator.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/sim/wound.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components::test {
namespace {

const KDL::Frame kWoundPose(KDL::Rotation::RotZ(-0.4), KDL::Vector(0.3, 0.05, 0.02));  // W_T_wound

struct Bench {
  core::LockstepClock clock;
  WoundSimulator patient{"Patient"};
  StitchPlannerComponent planner{"StitchPlanner"};
  core::OutputPort<KDL::Frame> tool{"tool", "", "m"}, stick{"stick", "", "m"};
  core::OutputPort<int> actuations{"actuations", "", "1"};  // the robot's Endo Stitch count
  int actuated = 0;
  core::InputPort<core::Event> events{"events", "", ""};
  core::InputPort<KDL::Frame> right{"right", "", "m"}, left{"left", "", "m"};
  core::InputPort<int> index{"index", "", "1"}, planned{"planned", "", "1"};
  core::InputPort<double> gap{"gap", "", "m"}, stitch_gap{"stitchGap", "", "m"};
  std::vector<std::string> said;
  const sim::Wound model{sim::WoundModel{}};

  explicit Bench(bool connect_edges = true) {
    clock.add(patient, std::chrono::milliseconds(1));
    clock.add(planner, std::chrono::milliseconds(1));
    if (connect_edges) core::connectPorts(patient.port("woundEdges"), planner.port("woundEdges"));
    core::connectPorts(tool, patient.port("toolTipPose"));
    core::connectPorts(stick, patient.port("stickTipPose"));
    core::connectPorts(actuations, patient.port("endoStitchActuations"));
    core::connectPorts(planner.port("events"), events, core::ConnPolicy::buffer(8));
    core::connectPorts(planner.port("rightStitchPose"), right);
    core::connectPorts(planner.port("leftStitchPose"), left);
    core::connectPorts(planner.port("stitchIndex"), index);
    core::connectPorts(planner.port("plannedStitches"), planned);
    core::connectPorts(planner.port("stitchGap"), gap);
    core::connectPorts(patient.port("maxStitchGap"), stitch_gap);
    patient.setProperty("wound_pose", kWoundPose);
  }
  void start() {
    ASSERT_TRUE(patient.configure());
    ASSERT_TRUE(planner.configure());
    ASSERT_TRUE(patient.start());
    ASSERT_TRUE(planner.start());
  }
  void step(const KDL::Vector& tip_in_world) {
    tool.write(KDL::Frame(tip_in_world));
    stick.write(KDL::Frame(KDL::Vector(1.0, 1.0, 1.0)));
    clock.advance(std::chrono::milliseconds(1));
    for (core::Event e; events.read(e) == core::FlowStatus::NewData;) said.push_back(e.name.str());
  }
  std::string ask() {
    said.clear();
    planner.call<void>("askStitch");
    step(KDL::Vector(0.3, 0.05, 0.1));
    return said.empty() ? "(nothing)" : said.back();
  }
  template <class T>
  T read(core::InputPort<T>& port) {
    T v{};
    (void)port.read(v);
    return v;
  }
  /// Applies the planned stitch on the simulated wound and pulls it closed (world frame).
  void applyPlanned() {
    const KDL::Frame r = read(right), l = read(left);
    actuations.write(++actuated);
    step(r.p);
    actuations.write(++actuated);
    step(l.p);
    const KDL::Vector up = l.M.UnitZ();  // out of the skin
    for (double lift = 0.0; lift < 0.08 && read(stitch_gap) >= 0.0005; lift += 2e-4) step(l.p + up * lift);
    step(l.p);
  }
};

TEST(StitchPlanner, PlansOnTheWoundsEdgesFollowsItAsItClosesAndSaysWhenDone) {
  Bench b;
  b.start();
  b.step(KDL::Vector(0.3, 0.05, 0.1));  // the patient publishes its edges
  ASSERT_EQ(b.ask(), "e_stitch_planned");
  EXPECT_EQ(b.read(b.planned), 4);
  EXPECT_EQ(b.read(b.index), 0);
  const KDL::Frame r = b.read(b.right);
  EXPECT_NEAR((r.p - kWoundPose * b.model.stitchPoint(sim::WoundSide::Right, 0.008)).Norm(), 0.0, 1e-5);
  EXPECT_NEAR(KDL::dot(r.M.UnitZ(), kWoundPose.M.UnitZ()), 1.0, 1e-9);  // out of the skin
  EXPECT_NEAR(KDL::dot(r.M.UnitX(), kWoundPose.M.UnitX()), 1.0, 1e-9);  // along the cut

  // Asking again before nextStitch plans the same stitch (a retry after a miss).
  ASSERT_EQ(b.ask(), "e_stitch_planned");
  EXPECT_EQ(b.read(b.index), 0);

  b.planner.call<void>("nextStitch");
  ASSERT_EQ(b.ask(), "e_stitch_planned");
  const double second_open = b.read(b.gap);
  b.planner.call<void>("restartPlan");
  ASSERT_EQ(b.ask(), "e_stitch_planned");
  ASSERT_EQ(b.read(b.index), 0);

  for (int k = 0; k < 4; ++k) {
    ASSERT_EQ(b.read(b.index), k);
    b.applyPlanned();
    b.planner.call<void>("nextStitch");
    const std::string answer = b.ask();
    if (k == 0) {
      ASSERT_EQ(answer, "e_stitch_planned");
      EXPECT_LT(b.read(b.gap), second_open - 1e-4);  // the first pull narrowed the second place
    }
    if (k == 3) {
      EXPECT_EQ(answer, "e_stitches_done");
    }
  }
}

TEST(StitchPlanner, WithoutEdgesItSaysSo) {
  Bench b(false);
  b.start();
  EXPECT_EQ(b.ask(), "e_no_wound_data");
}

TEST(StitchPlanner, BadPropertiesAreRefusedNamingThem) {
  Bench b;
  b.planner.setProperty("spacing", -0.01);
  EXPECT_EQ(b.planner.configure().message,
            "component 'StitchPlanner': stitch plan: spacing is -0.01 m: expected a finite value > 0 m");
  b.planner.setProperty("spacing", 0.008);
  b.planner.setProperty("skin_normal", KDL::Vector(0, 0, 2));
  EXPECT_EQ(b.planner.configure().message,
            "component 'StitchPlanner': property skin_normal has length 2.000000; expected a unit vector out of the "
            "skin (world frame)");
}

TEST(StitchPlanner, AnsweringAllocatesNothing) {
  Bench b;
  b.start();
  b.step(KDL::Vector(0.3, 0.05, 0.1));
  ASSERT_EQ(b.ask(), "e_stitch_planned");
  for (int i = 0; i < 5; ++i) b.step(KDL::Vector(0.3, 0.05, 0.1));  // every slot of the edges' channel filled once
  b.planner.call<void>("nextStitch");
  b.planner.call<void>("askStitch");  // marked now, answered in the step measured below
  const long calls = test_support::allocationsDuring([&] { b.clock.advance(std::chrono::milliseconds(1)); });
  EXPECT_EQ(calls, 0);
  core::Event e;
  ASSERT_EQ(b.events.read(e), core::FlowStatus::NewData);
  EXPECT_EQ(e.name.str(), "e_stitch_planned");
  EXPECT_EQ(b.read(b.index), 1);
}

}  // namespace
}  // namespace cobra::components::test
