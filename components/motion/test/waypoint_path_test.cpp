// WaypointPath on the lockstep clock: the path from the measured pose through the waypoints, the
// requests answered in the next step, the refusals naming the pose, no allocation when answering,
// and a CartesianTrajectoryGenerator following what it sends.
#include "cobra/components/motion/waypoint_path.hpp"

#include <gtest/gtest.h>

#include "cobra/components/motion/cartesian_trajectory_generator.hpp"
#include "cobra/core/core.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

// Two poses: 10 cm along x with the tool down, then 10 cm along y turned 90 degrees about z.
const std::vector<double> kWaypoints = {0.4, 0.0, 0.3, 1.0, 0.0, 0.0, 0.0,  //
                                        0.4, 0.1, 0.3, 0.70710678, 0.70710678, 0.0, 0.0};

struct Bench {
  core::LockstepClock clock;
  WaypointPath source{"ScanPath"};
  core::OutputPort<KDL::Frame> measured{"measured", "", "m"};
  core::InputPort<trajectory::MultiAxisPath> path{"path", "", "m, 1"};
  core::InputPort<core::Event> events{"events", "", ""};

  Bench() {
    source.setProperty("waypoints", kWaypoints);
    clock.add(source, 1ms);
    core::connectPorts(measured, source.port("measPose"));
    core::connectPorts(source.port("path"), path);
    core::connectPorts(source.port("events"), events, core::ConnPolicy::buffer(16));
  }
  std::vector<std::string> takeEvents() {
    std::vector<std::string> out;
    for (core::Event e; events.read(e) == core::FlowStatus::NewData;) out.push_back(e.name.str());
    return out;
  }
  /// askPath() answered in the next step: the path it sent, one frame per pose (empty: none sent).
  std::vector<std::vector<KDL::Frame>> askedPath() {
    source.call<void>("askPath");
    clock.advance(1ms);
    EXPECT_EQ(takeEvents(), (std::vector<std::string>{"e_path_sent"}));
    trajectory::MultiAxisPath sent;
    if (path.read(sent) != core::FlowStatus::NewData) return {};
    return decodeCartesianPath(sent, 1);
  }
};

TEST(WaypointPath, APathStartsAtTheMeasuredPoseAndGoesThroughTheWaypoints) {
  Bench b;
  ASSERT_TRUE(b.source.configure());
  ASSERT_TRUE(b.source.start());
  EXPECT_EQ(b.source.call<int>("waypointCount"), 2);
  b.source.call<void>("askPath");  // no measured pose yet
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_no_data"}));

  const KDL::Frame start(KDL::Rotation::RPY(3.14159, 0.0, 0.2), KDL::Vector(0.3, -0.05, 0.35));
  b.measured.write(start);
  b.clock.advance(1ms);
  EXPECT_TRUE(b.takeEvents().empty());  // a request is answered once
  const auto frames = b.askedPath();
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_TRUE(KDL::Equal(frames[0][0], start, 1e-9));
  EXPECT_TRUE(KDL::Equal(frames[1][0], KDL::Frame(KDL::Rotation::RotX(M_PI), KDL::Vector(0.4, 0.0, 0.3)), 1e-9));
  EXPECT_TRUE(KDL::Equal(frames[2][0].p, KDL::Vector(0.4, 0.1, 0.3), 1e-9));
}

// relative = true: the waypoints are offsets from wherever the tool is when the path is asked for
// (a retreat of 2 mm up, then 1 mm along x turned 90 degrees about base z), from two poses.
TEST(WaypointPath, RelativeWaypointsAreOffsetsFromTheMeasuredPose) {
  Bench b;
  b.source.setProperty("waypoints", std::vector<double>{0.0, 0.0, 0.002, 0.0, 0.0, 0.0, 1.0,  //
                                                        0.001, 0.0, 0.002, 0.0, 0.0, 0.70710678, 0.70710678});
  b.source.setProperty("relative", true);
  ASSERT_TRUE(b.source.configure());
  ASSERT_TRUE(b.source.start());
  for (const KDL::Frame& start : {KDL::Frame(KDL::Rotation::RPY(M_PI, 0.0, 0.2), KDL::Vector(0.35, -0.03, 0.109)),
                                  KDL::Frame(KDL::Rotation::RotX(M_PI), KDL::Vector(0.2, 0.1, 0.05))}) {
    b.measured.write(start);
    const auto frames = b.askedPath();
    ASSERT_EQ(frames.size(), 3u);
    EXPECT_TRUE(KDL::Equal(frames[0][0], start, 1e-9));
    EXPECT_TRUE(KDL::Equal(frames[1][0], KDL::Frame(start.M, start.p + KDL::Vector(0.0, 0.0, 0.002)), 1e-9));
    EXPECT_TRUE(KDL::Equal(frames[2][0], KDL::Frame(KDL::Rotation::RotZ(M_PI / 2) * start.M,
                                                    start.p + KDL::Vector(0.001, 0.0, 0.002)), 1e-6));
  }
}

TEST(WaypointPath, BadWaypointsAreRefusedNamingThePose) {
  {
    WaypointPath w("ScanPath");
    w.setProperty("waypoints", std::vector<double>{0.1, 0.2, 0.3});
    EXPECT_CONTAINS(w.configure().message,
                    "component 'ScanPath': property waypoints has 3 values; expected 7 per pose (x y z [m] qx qy qz qw)");
  }
  {
    WaypointPath w("ScanPath");
    std::vector<double> values = kWaypoints;
    values[10] = values[11] = values[12] = values[13] = 0.0;  // pose 2: no quaternion
    w.setProperty("waypoints", values);
    EXPECT_CONTAINS(w.configure().message, "property waypoints: pose 2 needs finite values and a non-zero quaternion");
  }
}

// Answering askPath() with `relative` waypoints or not: no allocation once the buffers are sized.
void expectAnsweringAllocatesNothing(bool relative) {
  Bench b;
  b.source.setProperty("relative", relative);
  ASSERT_TRUE(b.source.configure());
  ASSERT_TRUE(b.source.start());
  b.measured.write(KDL::Frame(KDL::Vector(0.3, 0.0, 0.3)));
  for (int i = 0; i < 3; ++i) {  // the first answers size the connection's buffers
    b.source.call<void>("askPath");
    b.clock.advance(1ms);
  }
  (void)b.takeEvents();
  long allocations = 0;
  for (int i = 0; i < 10; ++i) {
    b.source.call<void>("askPath");  // the by-name call itself is not real-time (it packs its arguments)
    allocations += test_support::allocationsDuring([&] {
      b.measured.write(KDL::Frame(KDL::Vector(0.3, 0.001 * i, 0.3)));
      b.clock.advance(1ms);
    });
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(b.takeEvents().size(), 10u);
}

// Both ways: waypoints as poses, and as offsets from the measured pose (relative).
TEST(WaypointPath, AnsweringARequestAllocatesNothing) {
  for (const bool relative : {false, true}) {
    SCOPED_TRACE(relative ? "relative" : "poses");
    expectAnsweringAllocatesNothing(relative);
  }
}

TEST(WaypointPath, TheTrajectoryGeneratorFollowsThePathItSends) {
  Bench b;
  CartesianTrajectoryGenerator generator("TrajGen");
  generator.setProperty("max_vel", 0.1);
  generator.setProperty("max_ang_vel", 1.0);
  b.clock.add(generator, 1ms);
  core::connectPorts(b.source.port("path"), generator.port("plannedPath"));
  ASSERT_TRUE(b.source.configure());
  ASSERT_TRUE(generator.configure());
  core::InputPort<KDL::Frame> commanded{"commanded", "", "m"};
  core::connectPorts(generator.port("desCartPose_1"), commanded);
  ASSERT_TRUE(b.source.start());
  ASSERT_TRUE(generator.start());
  b.measured.write(KDL::Frame(KDL::Rotation::RotX(M_PI), KDL::Vector(0.3, 0.0, 0.3)));
  b.clock.advance(1ms);
  b.source.call<void>("askPath");
  b.clock.advance(2ms);
  generator.call<void>("askGenerateTraj");
  b.clock.advance(2ms);
  generator.call<void>("askStartMove");
  for (int ms = 0; ms < 10000 && generator.status() != CartesianTrajectoryGenerator::Status::WaitPath; ++ms)
    b.clock.advance(1ms);
  KDL::Frame end;
  ASSERT_NE(commanded.read(end), core::FlowStatus::NoData);
  EXPECT_TRUE(KDL::Equal(end.p, KDL::Vector(0.4, 0.1, 0.3), 1e-6));
}

}  // namespace
}  // namespace cobra::components
