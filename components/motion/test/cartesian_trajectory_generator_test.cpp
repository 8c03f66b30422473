// The Multi-Arm Cartesian Trajectory Generator (thesis §4.5.2, Fig. 4.12) on the lockstep clock.
#include "cobra/components/motion/cartesian_trajectory_generator.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "cobra/core/core.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;
using Generator = CartesianTrajectoryGenerator;

KDL::Frame pose(double x, double y, double z, double rz) { return {KDL::Rotation::RotZ(rz), KDL::Vector(x, y, z)}; }

/// A generator for two arms on a 1 kHz lockstep clock, with probes on its ports and events.
struct Bench {
  Generator generator{"TrajGen"};
  core::LockstepClock clock;
  core::OutputPort<trajectory::MultiAxisPath> planner{"plannedPath", "test planner", "m"};
  core::InputPort<core::Event> events{"events", "the generator's events", ""};
  std::vector<std::unique_ptr<core::InputPort<KDL::Frame>>> poses;
  std::vector<std::unique_ptr<core::InputPort<KDL::Twist>>> twists;

  explicit Bench(int arms = 2) {
    generator.setProperty("arms_num", arms);
    generator.setProperty("max_vel", 0.1);
    generator.setProperty("max_ang_vel", 1.0);
    generator.setProperty("time_acc", 0.1);
    generator.setProperty("stop_time", 0.2);
    clock.add(generator, 1ms);
    core::connectPorts(generator.port("events"), events, core::ConnPolicy::buffer(64));
    EXPECT_TRUE(generator.configure());
    core::connectPorts(planner, generator.port("plannedPath"));
    for (int i = 1; i <= arms; ++i) {
      poses.push_back(std::make_unique<core::InputPort<KDL::Frame>>("pose", "", "m"));
      twists.push_back(std::make_unique<core::InputPort<KDL::Twist>>("twist", "", "m/s"));
      core::connectPorts(generator.port("desCartPose_" + std::to_string(i)), *poses.back());
      core::connectPorts(generator.port("desCartTwist_" + std::to_string(i)), *twists.back());
    }
    EXPECT_TRUE(generator.start());
    EXPECT_EQ(takeEvents(), (std::vector<std::string>{"e_initialized", "e_wait_path"}));
  }
  /// Sends kTwoArmPath, has its trajectory generated (answered in the next step) and starts it.
  void startMoving();
  /// Sends `path` and has its trajectory generated; a started generator keeps its last set-points.
  void generate(const std::vector<std::vector<KDL::Frame>>& path) {
    planner.write(encodeCartesianPath(path));
    clock.advance(1ms);
    call("askGenerateTraj");
    clock.advance(1ms);
  }
  /// Moves along `path` to its end (e_motion_done): every arm's last set-point is then its last waypoint.
  void moveThrough(const std::vector<std::vector<KDL::Frame>>& path) {
    generate(path);
    ASSERT_NE(generator.trajectory(), nullptr);
    call("askStartMove");
    clock.advance(std::chrono::milliseconds(static_cast<int>(std::ceil(generator.trajectory()->duration() * 1e3)) + 2));
    ASSERT_EQ(status(), "WaitPath");
    takeEvents();
  }
  /// Events emitted since the last call, in order.
  std::vector<std::string> takeEvents() {
    std::vector<std::string> names;
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) names.push_back(e.name.str());
    return names;
  }
  KDL::Frame lastPose(std::size_t arm) {
    KDL::Frame f;
    EXPECT_NE(poses[arm]->read(f), core::FlowStatus::NoData);
    return f;
  }
  KDL::Twist lastTwist(std::size_t arm) {
    KDL::Twist t;
    EXPECT_NE(twists[arm]->read(t), core::FlowStatus::NoData);
    return t;
  }
  void call(const char* operation) { generator.call<void>(operation); }
  std::string status() { return generator.call<std::string>("status"); }
};

const std::vector<std::vector<KDL::Frame>> kTwoArmPath = {
    {pose(0.0, 0.0, 0.1, 0.0), pose(0.5, 0.0, 0.1, 0.0)},
    {pose(0.05, 0.02, 0.12, 0.3), pose(0.45, -0.03, 0.1, -0.2)},
    {pose(0.08, 0.05, 0.15, 0.5), pose(0.42, -0.05, 0.08, -0.4)},
};

void Bench::startMoving() {
  generate(kTwoArmPath);
  call("askStartMove");
}

/// `frame` moved by `dx` m along the base x axis.
KDL::Frame shifted(const KDL::Frame& frame, double dx) { return {frame.M, frame.p + KDL::Vector(dx, 0.0, 0.0)}; }

TEST(CartesianTrajectoryGenerator, MakesOnePoseAndOneTwistPortPerArmAtConfigure) {
  Generator g("TrajGen");
  EXPECT_EQ(g.call<std::string>("status"), "NotInitialized");
  g.setProperty("arms_num", 3);
  ASSERT_TRUE(g.configure());
  for (const char* name : {"desCartPose_1", "desCartTwist_1", "desCartPose_3", "desCartTwist_3"})
    EXPECT_NE(g.findPort(name), nullptr) << name;
  g.setProperty("arms_num", 1);
  ASSERT_TRUE(g.configure());
  EXPECT_EQ(g.findPort("desCartPose_2"), nullptr);
  EXPECT_EQ(g.port("desCartPose_1").unit(), "m");
  EXPECT_EQ(g.call<std::string>("status"), "Initialized");
  ASSERT_TRUE(g.cleanup());
  EXPECT_EQ(g.call<std::string>("status"), "NotInitialized");
}

TEST(CartesianTrajectoryGenerator, FollowsFigure412FromPathToMotionDone) {
  Bench b;
  EXPECT_EQ(b.status(), "WaitPath");
  b.call("askGenerateTraj");  // answered in the generator's next step
  b.call("askStartMove");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_no_path", "e_no_trajectory"}));

  b.planner.write(encodeCartesianPath(kTwoArmPath));
  b.clock.advance(1ms);
  EXPECT_EQ(b.status(), "PathReady");
  b.call("askGenerateTraj");
  EXPECT_EQ(b.status(), "PathReady");  // the request is answered in the generator's next step
  b.clock.advance(1ms);
  EXPECT_EQ(b.status(), "TrajectoryReady");
  const trajectory::CartesianTrajectory reference(kTwoArmPath, {0.1, 1.0, 0.1, 0.1}, 5);
  ASSERT_NE(b.generator.trajectory(), nullptr);
  EXPECT_DOUBLE_EQ(b.generator.trajectory()->duration(), reference.duration());

  b.call("askStartMove");
  // Answered in the next step, which writes the first set-point (t = 0 of the motion); then one per ms.
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_path_ready", "e_generating_trajectory", "e_trajectory_ready",
                                                      "e_moving"}));
  const auto steps = static_cast<int>(std::floor(reference.duration() / 2 / 1e-3));
  b.clock.advance(std::chrono::milliseconds(steps));
  KDL::Frame expected_pose[2];
  KDL::Twist expected_twist[2];
  reference.evaluate(steps * 1e-3, expected_pose, expected_twist);
  for (std::size_t arm = 0; arm < 2; ++arm) {
    EXPECT_TRUE(KDL::Equal(b.lastPose(arm), expected_pose[arm], 1e-12)) << "arm " << arm;
    EXPECT_TRUE(KDL::Equal(b.lastTwist(arm), expected_twist[arm], 1e-12)) << "arm " << arm;
  }
  EXPECT_EQ(b.status(), "Moving");
  b.clock.advance(std::chrono::milliseconds(static_cast<int>(reference.duration() * 1e3)));
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_motion_done", "e_wait_path"}));
  EXPECT_EQ(b.status(), "WaitPath");
  for (std::size_t arm = 0; arm < 2; ++arm) {
    EXPECT_TRUE(KDL::Equal(b.lastPose(arm), kTwoArmPath.back()[arm], 1e-9)) << "arm " << arm;
    EXPECT_TRUE(KDL::Equal(b.lastTwist(arm), KDL::Twist::Zero(), 1e-9)) << "arm " << arm;
  }
}

TEST(CartesianTrajectoryGenerator, StopsFromAnyStateToRestWithinStopTime) {
  Bench b;
  b.startMoving();
  b.clock.advance(400ms);  // mid-motion: moving fast
  const KDL::Twist before = b.lastTwist(0);
  ASSERT_GT(before.vel.Norm(), 0.01);
  const KDL::Frame at_stop = b.lastPose(0);
  b.call("askStopMove");
  EXPECT_EQ(b.status(), "Moving");  // answered in the generator's next step
  b.clock.advance(1ms);  // the stop starts from the set-point due then: no jump in velocity
  EXPECT_EQ(b.status(), "GeneratingStop");
  const KDL::Twist first = b.lastTwist(0);
  EXPECT_LT((first.vel - before.vel).Norm() + (first.rot - before.rot).Norm(), 2e-3);
  b.clock.advance(249ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_path_ready", "e_generating_trajectory", "e_trajectory_ready",
                                                      "e_moving", "e_generating_stop", "e_motion_stopped",
                                                      "e_wait_path"}));
  EXPECT_EQ(b.status(), "WaitPath");
  const KDL::Twist after = b.lastTwist(0);
  EXPECT_LT(after.vel.Norm() + after.rot.Norm(), 1e-9);
  // It kept going the way it went, and no further than v·T (the stop polynomial never overshoots).
  const KDL::Vector travelled = b.lastPose(0).p - at_stop.p;
  EXPECT_GT(KDL::dot(travelled, before.vel), 0.0);
  EXPECT_LT(travelled.Norm(), before.vel.Norm() * 0.2 + 1e-3);
  b.call("askStopMove");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(), std::vector<std::string>{"e_not_moving"});
}

// The robot of arm 1 refused a command and holds 0.5 mm behind the set-point: the motion ends at
// once, arm 1 at its held pose and arm 2 at its set-point, both at rest; nothing resumes the old
// trajectory, and the next path starts from the held pose.
TEST(CartesianTrajectoryGenerator, AHeldArmEndsTheMotionThereAndTheNextPathStartsFromIt) {
  Bench b;
  core::OutputPort<KDL::Frame> robot{"heldCartPose", "", "m"};
  core::connectPorts(robot, b.generator.port("heldPose_1"));
  b.startMoving();
  b.clock.advance(400ms);
  ASSERT_GT(b.lastTwist(0).vel.Norm(), 0.01);
  const KDL::Frame arm2 = b.lastPose(1);
  const KDL::Frame held(b.lastPose(0).M, b.lastPose(0).p - KDL::Vector(0.0005, 0, 0));
  b.takeEvents();
  robot.write(held);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { b.clock.advance(1ms); }), 0);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_resynced", "e_wait_path"}));
  EXPECT_EQ(b.status(), "WaitPath");
  EXPECT_TRUE(KDL::Equal(b.lastPose(0), held, 1e-15));
  EXPECT_TRUE(KDL::Equal(b.lastPose(1), arm2, 1e-15));
  for (std::size_t arm = 0; arm < 2; ++arm) EXPECT_TRUE(KDL::Equal(b.lastTwist(arm), KDL::Twist::Zero(), 1e-15));
  // At rest there: no set-point follows, the old trajectory cannot be started again.
  b.clock.advance(100ms);
  KDL::Frame f;
  EXPECT_EQ(b.poses[0]->read(f), core::FlowStatus::OldData);
  b.call("askStartMove");
  b.call("askStopMove");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_no_trajectory", "e_not_moving"}));
  // Held again while waiting (the robot still refusing): the set-point follows, the state stays.
  const KDL::Frame later(held.M, held.p + KDL::Vector(0, 0.0002, 0));
  robot.write(later);
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(), std::vector<std::string>{"e_resynced"});
  EXPECT_TRUE(KDL::Equal(b.lastPose(0), later, 1e-15));
  // A re-plan from the measured pose (1 mm from the held one): its first set-point is the held pose.
  b.planner.write(encodeCartesianPath({{KDL::Frame(later.M, later.p + KDL::Vector(0, 0, 0.001)), arm2},
                                       {pose(0.3, 0.1, 0.1, 0.1),
                                        KDL::Frame(arm2.M, arm2.p + KDL::Vector(0.01, 0, 0))}}));
  b.clock.advance(1ms);
  b.call("askGenerateTraj");
  b.clock.advance(1ms);
  b.call("askStartMove");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_path_ready", "e_generating_trajectory", "e_trajectory_ready",
                                                      "e_moving"}));
  EXPECT_TRUE(KDL::Equal(b.lastPose(0), later, 1e-12));
  KDL::Frame previous = later;
  for (int i = 0; i < 500; ++i) {
    b.clock.advance(1ms);
    ASSERT_LT((b.lastPose(0).p - previous.p).Norm(), 1e-3) << "ms " << i;
    previous = b.lastPose(0);
  }
}

// A held pose in every other state: Trajectory ready and a stop motion end in WaitPath as well.
TEST(CartesianTrajectoryGenerator, AHeldArmDropsAReadyTrajectoryAndEndsAStopMotion) {
  Bench b;
  core::OutputPort<KDL::Frame> robot{"heldCartPose", "", "m"};
  core::connectPorts(robot, b.generator.port("heldPose_2"));
  b.planner.write(encodeCartesianPath(kTwoArmPath));
  b.clock.advance(1ms);
  b.call("askGenerateTraj");
  b.clock.advance(1ms);
  b.takeEvents();
  robot.write(kTwoArmPath[0][1]);
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_resynced", "e_wait_path"}));
  KDL::Frame f;
  EXPECT_EQ(b.poses[0]->read(f), core::FlowStatus::NoData);  // arm 1 had no set-point to rest at
  EXPECT_TRUE(KDL::Equal(b.lastPose(1), kTwoArmPath[0][1], 1e-15));
  b.call("askStartMove");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(), std::vector<std::string>{"e_no_trajectory"});

  b.startMoving();
  b.clock.advance(300ms);
  b.call("askStopMove");
  b.clock.advance(50ms);
  EXPECT_EQ(b.status(), "GeneratingStop");
  b.takeEvents();
  robot.write(b.lastPose(1));
  b.clock.advance(1ms);
  // The stop asked for ends at the held pose: answered there, not again later.
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_resynced", "e_motion_stopped", "e_wait_path"}));
  b.clock.advance(300ms);
  EXPECT_EQ(b.takeEvents(), std::vector<std::string>{});
}

TEST(CartesianTrajectoryGenerator, AMalformedPathFailsWithAReason) {
  Bench b;
  trajectory::MultiAxisPath bad({{0, 0, 0, 0, 0, 0, 1}, {0.1, 0, 0, 0, 0, 0, 1}});  // one arm, two expected
  b.planner.write(bad);
  b.clock.advance(1ms);
  b.call("askGenerateTraj");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(),
            (std::vector<std::string>{"e_path_ready", "e_generating_trajectory", "e_traj_failed", "e_path_ready"}));
  EXPECT_EQ(b.generator.call<std::string>("lastFailure"),
            "plannedPath: waypoint 0 has 7 values; 2 arm(s) need 14 (x, y, z, qx, qy, qz, qw per arm)");
  EXPECT_EQ(b.status(), "PathReady");
}

TEST(CartesianTrajectoryGenerator, AskGenerateTrajWhileMovingAnswersBusyAndKeepsMoving) {
  Bench b;
  b.startMoving();
  b.clock.advance(100ms);
  b.takeEvents();
  const trajectory::CartesianTrajectory* followed = b.generator.trajectory();
  b.call("askGenerateTraj");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(), std::vector<std::string>{"e_busy"});
  EXPECT_EQ(b.status(), "Moving");
  EXPECT_EQ(b.generator.trajectory(), followed);
}

TEST(CartesianTrajectoryGenerator, ContinuesEveryArmFromItsLastSetPointWhenThePathHasMoreWaypointsThanArms) {
  Bench b;  // two arms
  b.moveThrough(kTwoArmPath);
  const std::vector<KDL::Frame>& last = kTwoArmPath.back();
  // Three waypoints for two arms, starting 1 mm from each arm's last set-point (continue_tolerance 2 mm).
  const std::vector<std::vector<KDL::Frame>> next = {
      {shifted(last[0], 0.001), shifted(last[1], 0.001)},
      {pose(0.1, 0.1, 0.15, 0.2), pose(0.4, 0.0, 0.1, -0.1)},
      {pose(0.12, 0.1, 0.12, 0.1), pose(0.38, 0.02, 0.1, 0.0)},
  };
  b.generate(next);
  ASSERT_EQ(b.status(), "TrajectoryReady") << b.generator.call<std::string>("lastFailure");
  b.call("askStartMove");
  b.clock.advance(1ms);  // the first set-point: t = 0 of the motion
  for (std::size_t arm = 0; arm < 2; ++arm)
    EXPECT_TRUE(KDL::Equal(b.lastPose(arm), last[arm], 1e-9)) << "arm " << arm << " steps off its last set-point";
  // The waypoints after the first are followed as given.
  const trajectory::CartesianTrajectory& followed = *b.generator.trajectory();
  for (std::size_t arm = 0; arm < 2; ++arm) {
    KDL::Frame at;
    KDL::Twist twist;
    followed.evaluate(followed.duration(), arm, at, twist);
    EXPECT_TRUE(KDL::Equal(at, next.back()[arm], 1e-9)) << "arm " << arm;
  }
}

TEST(CartesianTrajectoryGenerator, ContinuationChangesOnlyEachArmsOwnFirstPose) {
  Bench b;  // two arms
  b.moveThrough(kTwoArmPath);
  const std::vector<KDL::Frame>& last = kTwoArmPath.back();
  // Arm 0 ends 0.5 mm from arm 1's last set-point: waypoint 1 of arm 0 is no first pose and stays as given.
  const std::vector<std::vector<KDL::Frame>> next = {
      {shifted(last[0], 0.001), shifted(last[1], -0.001)},
      {shifted(last[1], 0.0005), pose(0.6, 0.1, 0.1, 0.0)},
  };
  b.generate(next);
  ASSERT_EQ(b.status(), "TrajectoryReady") << b.generator.call<std::string>("lastFailure");
  const trajectory::CartesianTrajectory& followed = *b.generator.trajectory();
  KDL::Frame at;
  KDL::Twist twist;
  for (std::size_t arm = 0; arm < 2; ++arm) {
    followed.evaluate(0.0, arm, at, twist);
    EXPECT_TRUE(KDL::Equal(at, last[arm], 1e-9)) << "arm " << arm << " does not start from its last set-point";
    followed.evaluate(followed.duration(), arm, at, twist);
    EXPECT_TRUE(KDL::Equal(at, next[1][arm], 1e-9)) << "arm " << arm << " does not end at its waypoint 1";
  }
}

TEST(CartesianTrajectoryGenerator, StartRefusesAnActivityThatIsNotSampleTime) {
  Generator g("TrajGen");
  core::LockstepClock clock;
  clock.add(g, 2ms);
  ASSERT_TRUE(g.configure());
  const core::Result wrong = g.start();
  EXPECT_FALSE(wrong);
  EXPECT_CONTAINS(wrong.message, "sample_time is 0.001000 s but the activity period is 0.002000 s; set one to the other");
  Generator h("Other");
  ASSERT_TRUE(h.configure());
  EXPECT_CONTAINS(h.start().message, "needs a periodic activity");
}

TEST(CartesianTrajectoryGenerator, MovingAllocatesNothing) {
  Bench b;
  b.startMoving();
  b.clock.advance(5ms);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { b.clock.advance(300ms); }), 0);
  b.call("askStopMove");
  b.clock.advance(1ms);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { b.clock.advance(100ms); }), 0);
}

TEST(CartesianPathEncoding, RoundTripsFramesAndTextAndNamesBadWaypoints) {
  const trajectory::MultiAxisPath path = encodeCartesianPath(kTwoArmPath);
  ASSERT_EQ(path.size(), 3U);
  EXPECT_EQ(path.axisCount(), 14U);
  const auto frames = decodeCartesianPath(path, 2);
  for (std::size_t k = 0; k < frames.size(); ++k)
    for (std::size_t arm = 0; arm < 2; ++arm) EXPECT_TRUE(KDL::Equal(frames[k][arm], kTwoArmPath[k][arm], 1e-12));
  trajectory::MultiAxisPath parsed;
  ASSERT_TRUE(core::DataTypeTraits<trajectory::MultiAxisPath>::parse("[[1, 2], [3, 4.5]]", parsed));
  EXPECT_EQ(parsed, trajectory::MultiAxisPath({{1, 2}, {3, 4.5}}));
  EXPECT_EQ(core::DataTypeTraits<trajectory::MultiAxisPath>::print(parsed), "[[1, 2], [3, 4.5]]");
  EXPECT_FALSE(core::DataTypeTraits<trajectory::MultiAxisPath>::parse("[1, 2]", parsed));
  EXPECT_CONTAINS(cobra::test_support::messageOf([] {
                    decodeCartesianPath(trajectory::MultiAxisPath({{0, 0, 0, 0, 0, 0, 0}}), 1);
                  }),
                  "waypoint 0, arm 1: the quaternion has zero norm");
}

}  // namespace
}  // namespace cobra::components
