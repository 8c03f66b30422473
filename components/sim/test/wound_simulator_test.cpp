// WoundSimulator: on the lockstep clock, with the wound placed off the world's origin: an Endo
// Stitch actuation (the robot's actuation count rising) away from the edge is a miss with its
// reason and distance; both halves at the stitch points apply a stitch, each on the edge the tip
// is at; pulling the tool up tensions the thread and closes the gap; four
// stitches close the wound at each stitch; the stick hooks the thread; woundEdges carries the
// edges in the world, threadPath and stitchLines the thread; bad properties are refused naming them; updateHook allocates nothing.
#include "cobra/components/sim/wound_simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cobra/core/lockstep_clock.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components::test {
namespace {

const KDL::Frame kWoundPose(KDL::Rotation::RotZ(0.3), KDL::Vector(0.4, -0.1, 0.05));  // W_T_wound

struct Bench {
  core::LockstepClock clock;
  WoundSimulator patient{"Patient"};
  core::OutputPort<KDL::Frame> tool{"tool", "", "m"};
  core::OutputPort<KDL::Frame> stick{"stick", "", "m"};
  core::OutputPort<int> actuations{"actuations", "", "1"};  // the robot's Endo Stitch count
  core::OutputPort<core::Event> requests{"requests", "", ""};
  int actuated = 0;
  core::InputPort<core::Event> events{"events", "", ""};
  core::InputPort<double> tension{"tension", "", "N"}, widest{"widest", "", "m"}, miss_distance{"missDistance", "", "m"};
  core::InputPort<int> count{"count", "", "1"}, miss{"miss", "", "1"};
  core::InputPort<std::vector<double>> edges{"edges", "", "m"};
  std::vector<std::string> said;
  const sim::Wound model{sim::WoundModel{}};  // the same default wound, for its stitch points

  Bench() {
    clock.add(patient, std::chrono::milliseconds(1));
    core::connectPorts(tool, patient.port("toolTipPose"));
    core::connectPorts(stick, patient.port("stickTipPose"));
    core::connectPorts(actuations, patient.port("endoStitchActuations"));
    core::connectPorts(requests, patient.port("inputEvents"), core::ConnPolicy::buffer(8));
    core::connectPorts(patient.port("events"), events, core::ConnPolicy::buffer(16));
    core::connectPorts(patient.port("threadTension"), tension);
    core::connectPorts(patient.port("maxStitchGap"), widest);
    core::connectPorts(patient.port("missDistance"), miss_distance);
    core::connectPorts(patient.port("stitchCount"), count);
    core::connectPorts(patient.port("missReason"), miss);
    core::connectPorts(patient.port("woundEdges"), edges);
    patient.setProperty("wound_pose", kWoundPose);
  }
  void start() {
    ASSERT_TRUE(patient.configure());
    ASSERT_TRUE(patient.start());
  }
  /// One step with the tool at `tip` (wound frame) and the stick at `stick_tip` (wound frame).
  void step(const KDL::Vector& tip, const KDL::Vector& stick_tip = KDL::Vector(0.0, 0.05, 0.05)) {
    tool.write(KDL::Frame(kWoundPose * tip));
    stick.write(KDL::Frame(kWoundPose * stick_tip));
    clock.advance(std::chrono::milliseconds(1));
    for (core::Event e; events.read(e) == core::FlowStatus::NewData;) said.push_back(e.name.str());
  }
  /// The robot actuated the Endo Stitch once more with the tip at `tip` (wound frame).
  void actuate(const KDL::Vector& tip) {
    actuations.write(++actuated);
    step(tip);
  }
  template <class T>
  T read(core::InputPort<T>& port) {
    T v{};
    (void)port.read(v);
    return v;
  }
  /// Both halves at s = 20 mm, then the tool 15 mm up (within the slack): returns the tool's tip;
  /// `midway` is where the free thread's middle then is (wound frame).
  KDL::Vector stitchAndLift(KDL::Vector& midway) {
    actuate(model.stitchPoint(sim::WoundSide::Right, 0.02));
    const KDL::Vector tip = model.stitchPoint(sim::WoundSide::Left, 0.02);
    actuate(tip);
    const KDL::Vector up = tip + KDL::Vector(0, 0, 0.015);
    const KDL::Vector exit = model.edgePoint(sim::WoundSide::Left, 0.02, 0.0) + KDL::Vector(0, 0.004, 0);
    midway = (exit + up) * 0.5;
    return up;
  }
  /// Both halves at s, then the tool pulled up until the stitch's gap is below 0.5 mm.
  void stitch(double s) {
    actuate(model.stitchPoint(sim::WoundSide::Right, s));
    const KDL::Vector tip = model.stitchPoint(sim::WoundSide::Left, s);
    actuate(tip);
    for (double lift = 0.0; lift < 0.08 && read(widest) >= 0.0005; lift += 2e-4) step(tip + KDL::Vector(0, 0, lift));
    step(tip);
  }
};

TEST(WoundSimulator, AMissSaysWhyThenBothHalvesApplyAStitchThatThePullCloses) {
  Bench b;
  b.start();
  b.actuate(b.model.stitchPoint(sim::WoundSide::Right, 0.008) + KDL::Vector(0, 0, -0.0025));  // too deep
  EXPECT_EQ(b.said, (std::vector<std::string>{"e_stitch_missed"}));
  EXPECT_EQ(b.read(b.miss), static_cast<int>(sim::StitchMiss::FarFromEdge));
  EXPECT_NEAR(b.read(b.miss_distance), 0.0025, 1e-9);
  b.said.clear();
  b.stitch(0.008);
  EXPECT_EQ(b.said, (std::vector<std::string>{"e_stitch_applied", "e_stitch_applied"}));
  EXPECT_EQ(b.read(b.count), 1);
  EXPECT_LT(b.read(b.widest), 0.0005);
  EXPECT_EQ(b.read(b.tension), 0.0);  // the tool went back down: the thread is slack again
}

TEST(WoundSimulator, FourStitchesCloseTheWoundAtEachStitch) {
  Bench b;
  b.start();
  for (const double s : {0.008, 0.016, 0.024, 0.032}) b.stitch(s);
  EXPECT_EQ(b.read(b.count), 4);
  EXPECT_LT(b.read(b.widest), 0.0005);
  EXPECT_EQ(std::count(b.said.begin(), b.said.end(), "e_stitch_applied"), 8);
  EXPECT_EQ(std::count(b.said.begin(), b.said.end(), "e_thread_broken"), 0);
}

TEST(WoundSimulator, TheStickHooksTheThreadAndTheEdgesArePublishedInTheWorld) {
  Bench b;
  b.patient.setProperty("edge_samples", 5);
  b.start();
  KDL::Vector midway;
  const KDL::Vector up = b.stitchAndLift(midway);
  b.step(up, midway + KDL::Vector(0.001, 0, 0));
  EXPECT_EQ(b.said.back(), "e_thread_hooked");

  const std::vector<double> edges = b.read(b.edges);
  ASSERT_EQ(edges.size(), 30u);  // 5 samples × (right, left) × xyz
  const KDL::Vector left_middle(edges[12 + 3], edges[12 + 4], edges[12 + 5]);  // sample 2 = the middle
  EXPECT_NEAR((left_middle - kWoundPose * b.model.edgePoint(sim::WoundSide::Left, 0.02, 0.0)).Norm(), 0.0, 1e-12);
}

TEST(WoundSimulator, ThreadPathAndStitchLinesFollowTheStitchesTheStickAndTheTipInTheWorld) {
  Bench b;
  core::InputPort<std::vector<double>> thread{"thread", "", "m"}, lines{"lines", "", "m"};
  core::connectPorts(b.patient.port("threadPath"), thread);
  core::connectPorts(b.patient.port("stitchLines"), lines);
  b.start();
  const auto point = [](const std::vector<double>& v, std::size_t i) { return KDL::Vector(v[3 * i], v[3 * i + 1], v[3 * i + 2]); };
  const auto world = [](const KDL::Vector& wound_point) { return kWoundPose * wound_point; };
  b.step(KDL::Vector(0, 0, 0.01));
  EXPECT_TRUE(b.read(thread).empty());  // no stitch: the thread is on the needle
  EXPECT_TRUE(b.read(lines).empty());

  b.actuate(b.model.stitchPoint(sim::WoundSide::Right, 0.02));  // the right half only
  const KDL::Vector tip(0.0, 0.0, 0.02);
  b.step(tip);
  std::vector<double> path = b.read(thread), segments = b.read(lines);
  ASSERT_EQ(path.size(), 6u);  // the right skin point, the tip
  ASSERT_EQ(segments.size(), 6u);  // one segment: skin point to edge point
  EXPECT_NEAR((point(path, 1) - world(tip)).Norm(), 0.0, 1e-12);
  // The right skin point: bite beyond the (still open) right edge, on the skin.
  const double out = 0.5 * b.model.initialGap(0.02) + b.model.model().bite;
  EXPECT_NEAR((point(path, 0) - world(b.model.centre(0.02) - b.model.normal(0.02) * out)).Norm(), 0.0, 1e-12);
  EXPECT_NEAR((point(segments, 0) - point(path, 0)).Norm(), 0.0, 1e-12);
  EXPECT_NEAR((point(segments, 1) - world(b.model.stitchPoint(sim::WoundSide::Right, 0.02))).Norm(), 0.0, 1e-12);

  b.actuate(b.model.stitchPoint(sim::WoundSide::Left, 0.02));
  const KDL::Vector up = b.model.stitchPoint(sim::WoundSide::Left, 0.02) + KDL::Vector(0, 0, 0.015);
  const KDL::Vector midway = (b.model.edgePoint(sim::WoundSide::Left, 0.02, 0.0) + KDL::Vector(0, 0.004, 0) + up) * 0.5;
  b.step(up, midway + KDL::Vector(0.001, 0, 0));
  ASSERT_EQ(b.said.back(), "e_thread_hooked");
  path = b.read(thread), segments = b.read(lines);
  ASSERT_EQ(path.size(), 12u);  // right and left skin points, the bend round the stick, the tip
  EXPECT_NEAR((point(path, 3) - world(up)).Norm(), 0.0, 1e-12);
  EXPECT_LT((point(path, 2) - world(midway + KDL::Vector(0.001, 0, 0))).Norm(), 0.0025);  // within hook_radius of the stick
  ASSERT_EQ(segments.size(), 3u * 6u);  // two halves and the crossing
  const double gap = (point(segments, 4) - point(segments, 5)).Norm();  // the crossing: edge point to edge point
  EXPECT_GT(gap, 0.0);
  EXPECT_LE(gap, b.model.initialGap(0.02) + 1e-12);
}

TEST(WoundSimulator, TheHookedThreadsPullOnTheStickIsAForceAtTheStickTip) {
  Bench b;
  // stickTipPose is the stick's tip itself (the left tool frame), whatever the gripper's turn: the
  // pull is a force there, no torque about it.
  const KDL::Rotation gripper = KDL::Rotation::RPY(0.4, -0.3, 0.2);
  core::InputPort<KDL::Wrench> wrench{"wrench", "", "N, N·m"};
  core::connectPorts(b.patient.port("stickWrench"), wrench);
  b.start();
  KDL::Vector midway;
  const KDL::Vector up = b.stitchAndLift(midway);
  const auto stickAt = [&](const KDL::Vector& tip) {
    b.stick.write(KDL::Frame(gripper, kWoundPose * tip));
    b.tool.write(KDL::Frame(kWoundPose * up));
    b.clock.advance(std::chrono::milliseconds(1));
  };
  stickAt(midway);
  for (double aside = 0.0; aside < 0.012; aside += 2e-4) stickAt(midway - KDL::Vector(aside, 0.0, 0.0));
  const KDL::Wrench w = b.read(wrench);
  ASSERT_GT(w.force.Norm(), 0.1);  // the thread bent round the stick pulls on it
  EXPECT_EQ(w.torque.Norm(), 0.0);
}

TEST(WoundSimulator, SeveralActuationsInOneStepEachTryAHalfAndARestartedCountIsANewOrigin) {
  Bench b;
  b.start();
  b.actuations.write(b.actuated += 2);  // two actuations seen in one step at the right edge point
  b.step(b.model.stitchPoint(sim::WoundSide::Right, 0.01));
  // The first applies the right half; the second, on the same (right) edge, is refused.
  EXPECT_EQ(b.said, (std::vector<std::string>{"e_stitch_applied", "e_stitch_missed"}));
  EXPECT_EQ(b.read(b.miss), static_cast<int>(sim::StitchMiss::RightStillOpen));
  b.said.clear();
  b.actuated = 0;  // the robot restarted: 0 is the new origin, 1 the next actuation
  b.actuations.write(0);
  b.step(b.model.stitchPoint(sim::WoundSide::Left, 0.01));
  EXPECT_TRUE(b.said.empty());
  b.actuate(b.model.stitchPoint(sim::WoundSide::Left, 0.01));
  EXPECT_EQ(b.said, (std::vector<std::string>{"e_stitch_applied"}));
  EXPECT_EQ(b.read(b.count), 1);
}

TEST(WoundSimulator, TheReleaseEventLetsTheHookedThreadGo) {
  Bench b;
  b.start();
  KDL::Vector stick;
  const KDL::Vector up = b.stitchAndLift(stick);
  b.step(up, stick);
  ASSERT_EQ(b.said.back(), "e_thread_hooked");
  core::Event e;
  e.name = "e_release_thread";
  b.requests.write(e);
  // The stick withdraws up, away from the thread, which slides off it within release_time (0.2 s).
  for (int ms = 0; ms < 201; ++ms) b.step(up, stick + KDL::Vector(0.0, 0.0, 0.02));
  b.said.clear();
  b.step(up, stick);  // back where it hooked: caught again, so it had let go
  EXPECT_EQ(b.said, (std::vector<std::string>{"e_thread_hooked"}));
}

TEST(WoundSimulator, BadPropertiesAreRefusedNamingThem) {
  Bench b;
  b.patient.setProperty("cut", std::vector<double>{0.0, 0.0, 0.04});
  EXPECT_EQ(b.patient.configure().message, "component 'Patient': property cut has 3 numbers; expected x, y pairs (m) of at least 2 points of the cut's centreline");
  b.patient.setProperty("cut", std::vector<double>{-0.02, 0.0, 0.02, 0.0});
  b.patient.setProperty("breaking_tension", 0.0);
  EXPECT_EQ(b.patient.configure().message, "component 'Patient': thread: breaking_tension is 0 N: expected a finite value > 0 N");
}

TEST(WoundSimulator, UpdatesAllocateNothing) {
  Bench b;
  b.start();
  b.actuations.write(b.actuated);  // the robot publishes its count from its start
  b.step(KDL::Vector(0, 0, 0.01));
  const KDL::Frame right(kWoundPose * b.model.stitchPoint(sim::WoundSide::Right, 0.02));
  const KDL::Frame left(kWoundPose * b.model.stitchPoint(sim::WoundSide::Left, 0.02));
  const long calls = test_support::allocationsDuring([&] {
    for (int i = 0; i < 400; ++i) {  // 100 ms at the right point, then the left, pulled up 3 cm
      const bool first = i < 100;
      b.tool.write(first ? right : KDL::Frame(left.p + KDL::Vector(0, 0, 1e-4 * (i - 100))));
      b.stick.write(KDL::Frame(KDL::Vector(0.0, 0.5, 0.5)));
      if (i == 10 || i == 100) b.actuations.write(++b.actuated);
      b.clock.advance(std::chrono::milliseconds(1));
    }
  });
  EXPECT_EQ(calls, 0);
  EXPECT_EQ(b.read(b.count), 1);  // the loop did stitch and pull
  EXPECT_GT(b.read(b.tension), 0.0);
}

}  // namespace
}  // namespace cobra::components::test
