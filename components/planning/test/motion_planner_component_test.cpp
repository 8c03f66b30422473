// The MotionPlanner component (thesis §4.5.1) on the lockstep clock with the real robot models on
// the puncturing scene: askPlan answers e_plan_done with a path the CartesianTrajectoryGenerator
// follows, or e_plan_failed with the reason; configuration errors name the property.

#include "cobra/components/planning/motion_planner_component.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <span>
#include <filesystem>
#include <numbers>
#include <random>

#include "cobra/components/motion/cartesian_trajectory_generator.hpp"
#include "cobra/core/core.hpp"
#include "cobra/planning/robot_adapters.hpp"
#include "cobra/test_support/test_support.hpp"
#include "../../../planning/test/puncturing_tools.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;
constexpr double kPi = std::numbers::pi;

using planning::test::needleDown;
using planning::test::probeDown;
std::string scenes() { return planning::test::scenes().string(); }

// The probe goes from one side of the phantom to the other, low: the straight line crosses the
// phantom (planning/test/real_robots_test.cpp checks these states with the same models).
const KDL::Frame kNeedle = needleDown(0.0, 0.0, 0.2);
const KDL::Frame kProbeStart = probeDown(-0.2, 0.0, 0.06);
const KDL::Frame kProbeGoal = probeDown(0.25, 0.0, 0.06);

void configureScene(core::Component& c) {
  c.setProperty("models_folder", scenes());
  c.setProperty("scene_file", std::string("puncturing.scene"));
  // A work limit, as the deployment (controller.lua): the queries plan the same under any load,
  // where a wall-clock limit made them fail on a busy machine.
  c.setProperty("max_validity_checks", 600000);
  c.setProperty("first_bounds_low", std::vector<double>{-0.15, -0.15, 0.03});
  c.setProperty("first_bounds_high", std::vector<double>{0.15, 0.15, 0.3});
  c.setProperty("second_bounds_low", std::vector<double>{-0.3, -0.3, 0.03});
  c.setProperty("second_bounds_high", std::vector<double>{0.35, 0.3, 0.35});
}

/// Planner (triggered, period 0) and trajectory generator (1 ms) on one lockstep clock, with a
/// test "supervisor" writing the measured poses and the goal.
struct Bench {
  MotionPlannerComponent planner{"Planner"};
  CartesianTrajectoryGenerator generator{"TrajGen"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Frame> isur{"isur", "", "m"};
  core::OutputPort<KDL::Frame> ur5{"ur5", "", "m"};
  core::OutputPort<trajectory::MultiAxisPath> goal{"goal", "", "m"};
  core::InputPort<core::Event> events{"events", "", ""};
  core::InputPort<core::Event> generator_events{"generator_events", "", ""};
  core::InputPort<double> min_distance{"minDistance", "", "m"};
  core::InputPort<KDL::Frame> needle_set_point{"pose", "", "m"};

  Bench() {
    configureScene(planner);
    generator.setProperty("arms_num", 2);
    generator.setProperty("max_vel", 0.2);
    generator.setProperty("max_ang_vel", 1.0);
    generator.setProperty("time_acc", 0.05);
    clock.add(generator, 1ms);
    clock.add(planner, 0ns);
    core::connectPorts(planner.port("events"), events, core::ConnPolicy::buffer(64));
    core::connectPorts(generator.port("events"), generator_events, core::ConnPolicy::buffer(64));
    core::connectPorts(isur, planner.port("isurMeasPose"));
    core::connectPorts(ur5, planner.port("UR5MeasPose"));
    core::connectPorts(goal, planner.port("goalPoses"));
    core::connectPorts(planner.port("minDistance"), min_distance);
    core::connectPorts(planner.port("plannedPath"), generator.port("plannedPath"));
    EXPECT_TRUE(planner.configure());
    EXPECT_TRUE(generator.configure());
    core::connectPorts(generator.port("desCartPose_1"), needle_set_point);
    EXPECT_TRUE(planner.start());
    EXPECT_TRUE(generator.start());
  }
  std::vector<std::string> takeEvents(core::InputPort<core::Event>& port) {
    std::vector<std::string> names;
    core::Event e;
    while (port.read(e) == core::FlowStatus::NewData) names.push_back(e.name.str());
    return names;
  }
  void measure(const KDL::Frame& needle, const KDL::Frame& probe) {
    isur.write(needle);
    ur5.write(probe);
  }
};

TEST(MotionPlannerComponent, PlansAPathTheTrajectoryGeneratorFollows) {
  Bench b;
  b.measure(kNeedle, kProbeStart);
  b.goal.write(encodeCartesianPath({{kNeedle, kProbeGoal}}));
  b.clock.advance(1ms);
  double distance = 0.0;
  ASSERT_EQ(b.min_distance.read(distance), core::FlowStatus::NewData);
  EXPECT_GT(distance, 0.005);  // the measured state is valid
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  ASSERT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_done"}))
      << b.planner.call<std::string>("lastPlanResult");
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"), "solved: solved by RRTConnect");
  b.clock.advance(1ms);
  EXPECT_EQ(b.generator.call<std::string>("status"), "PathReady");
  b.generator.call<void>("askGenerateTraj");
  b.clock.advance(1ms);  // generated in the generator's next step
  b.generator.call<void>("askStartMove");
  b.clock.advance(20s);
  const std::vector<std::string> generator_events = b.takeEvents(b.generator_events);
  ASSERT_FALSE(generator_events.empty());
  EXPECT_EQ(generator_events.back(), "e_wait_path");
  EXPECT_NE(std::find(generator_events.begin(), generator_events.end(), "e_motion_done"), generator_events.end());
  // The generator ended at the goal: the needle where it was, the probe at its goal.
  const auto* trajectory = b.generator.trajectory();
  ASSERT_NE(trajectory, nullptr);
  std::vector<KDL::Frame> poses(2);
  std::vector<KDL::Twist> twists(2);
  trajectory->evaluate(trajectory->duration(), poses, twists);
  EXPECT_LT((poses[1].p - kProbeGoal.p).Norm(), 1e-6);
  EXPECT_LT((poses[0].p - kNeedle.p).Norm(), 1e-6);
}

TEST(MotionPlannerComponent, SameSeedSamePathInLockstep) {
  std::vector<trajectory::MultiAxisPath> paths;
  for (int run = 0; run < 2; ++run) {
    Bench b;
    core::InputPort<trajectory::MultiAxisPath> path{"path", "", "m"};
    core::connectPorts(b.planner.port("plannedPath"), path);
    b.measure(kNeedle, kProbeStart);
    b.goal.write(encodeCartesianPath({{kNeedle, kProbeGoal}}));
    b.clock.advance(1ms);
    b.planner.call<void>("askPlan");
    b.clock.advance(1ms);
    trajectory::MultiAxisPath p;
    ASSERT_EQ(path.read(p), core::FlowStatus::NewData);
    paths.push_back(p);
  }
  EXPECT_EQ(paths[0], paths[1]);
}

TEST(MotionPlannerComponent, PlansFromTheMeasuredJointsAndReportsAllowedContactsApart) {
  Bench b;
  core::OutputPort<KDL::JntArray> isur_joints{"isurJoints", "", "m, rad"};
  core::OutputPort<KDL::JntArray> ur5_joints{"ur5Joints", "", "rad"};
  core::InputPort<double> allowed{"allowed", "", "m"};
  core::InputPort<double> primitive{"primitive", "", "m"};
  core::connectPorts(isur_joints, b.planner.port("isurMeasJoints"));
  core::connectPorts(ur5_joints, b.planner.port("UR5MeasJoints"));
  core::connectPorts(b.planner.port("allowedContactDistance"), allowed);
  core::connectPorts(b.planner.port("primitiveContactDistance"), primitive);
  core::InputPort<std::vector<double>> pairs{"pairs", "", "m"};
  core::connectPorts(b.planner.port("pairDistances"), pairs);
  // The I-SUR at the simulated robot's start (apps/puncturing/deployment/world.lua), the UR5 on
  // that start's branch with the probe pressed onto the phantom.
  KDL::JntArray isur(8), ur5(6);
  const double isur_q[8] = {0.00202, 0.00249, 0.204398, 0, 0, 0.85, 0.55, 0};
  for (unsigned j = 0; j < 8; ++j) isur(j) = isur_q[j];
  planning::Ur5Model model;
  KDL::JntArray seed(6);
  const double ur5_q[6] = {0.798, -1.4495, -1.714, 1.5925, -1.571, -2.344};
  for (unsigned j = 0; j < 6; ++j) seed(j) = ur5_q[j];
  // The probe pressed 2 mm into the phantom's top (z = 0.1 m, world) in the UR5's base frame.
  const KDL::Frame ur5_base(KDL::Rotation::RotZ(kPi / 2), KDL::Vector(0.3, -0.5, 0.0));
  const KDL::Frame pressed = ur5_base.Inverse() * probeDown(0.1, -0.05, 0.098);
  ASSERT_EQ(model.inverseNear(std::span(&pressed, 1), std::span<const double>(seed.data.data(), 6),
                              std::span<double>(ur5.data.data(), 6)),
            planning::Reachability::Reachable);
  isur_joints.write(isur);
  ur5_joints.write(ur5);
  // The poses the joints give (what the robots' measCartPose would say).
  planning::IsurPuncturingModel isur_model;
  std::array<KDL::Frame, 6> links{};
  ASSERT_TRUE(isur_model.linkFramesAt(std::span<const double>(isur.data.data(), 8), links));
  const KDL::Frame needle_pose = KDL::Frame(KDL::Vector(0, -0.05, 1.0)) * links[5];
  b.measure(needle_pose, probeDown(0.1, -0.05, 0.098));
  b.clock.advance(1ms);
  double clearance = 0.0, contact = 1.0;
  ASSERT_EQ(b.min_distance.read(clearance), core::FlowStatus::NewData);
  ASSERT_EQ(allowed.read(contact), core::FlowStatus::NewData);
  EXPECT_EQ(contact, 0.0);  // the probe touches the skin: an allowed contact, reported apart
  // The needle's contact with the phantom (the scene's primitive contact), reported apart too:
  // its tip 0.26 m above the table, 0.16 m above the phantom's top.
  ASSERT_EQ(primitive.read(contact), core::FlowStatus::NewData);
  EXPECT_NEAR(contact, 0.16, 0.002);
  EXPECT_GT(clearance, b.planner.call<double>("clearanceThreshold"));  // nothing else is near
  EXPECT_EQ(b.planner.call<double>("clearanceThreshold"), 0.005);      // the scene's
  // Per pair of groups: the same state's distances, each at least the overall clearance, the
  // probe on the skin left out of ur5/environment like the UR5 base's fixed gap to the table.
  EXPECT_EQ(b.planner.call<std::string>("clearancePairs"),
            "macro/micro,macro/ur5,micro/ur5,micro/environment,ur5/environment");
  std::vector<double> per_pair;
  ASSERT_EQ(pairs.read(per_pair), core::FlowStatus::NewData);
  ASSERT_EQ(per_pair.size(), 5U);
  for (double d : per_pair) EXPECT_GE(d, clearance);
  EXPECT_GT(per_pair[4], 0.0) << "the probe touching the phantom is not this pair's distance";

  // The probe lifts 5 cm from where the joints say it is: planned from the joints.
  b.goal.write(encodeCartesianPath({{needle_pose, probeDown(0.1, -0.05, 0.148)}}));
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  ASSERT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_done"}))
      << b.planner.call<std::string>("lastPlanResult");

  // Goal alternatives that must leave room for a later straight motion of the probe (the needle
  // waiting at its goal): over to the needle's tip cannot be made, 2.8 cm down can. The first
  // alternative is refused before any search, the second taken.
  const KDL::Frame lifted = probeDown(0.1, -0.05, 0.148);
  const auto room = [&](const KDL::Frame& probe_to) {
    return std::vector<KDL::Frame>{needle_pose, lifted, needle_pose, lifted, needle_pose, lifted, needle_pose, probe_to};
  };
  const KDL::Frame at_needle = probeDown(-0.05, 0.05, 0.2);
  b.goal.write(encodeCartesianPath({room(at_needle), room(probeDown(0.1, -0.05, 0.12))}));
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  ASSERT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_done"}))
      << b.planner.call<std::string>("lastPlanResult");
  const std::string chosen = b.planner.call<std::string>("lastPlanResult");
  EXPECT_CONTAINS(chosen, "; goal 2 of 2 (goal 1 of 2 first (");
  EXPECT_CONTAINS(chosen, "invalid goal: the straight motion from (-0.0503, 0.0497, 0.2606) m and (0.1000, -0.0500, "
                          "0.1480) m to (-0.0503, 0.0497, 0.2606) m and (-0.0500, 0.0500, 0.2000) m cannot be made: "
                          "too close: micro/ur5");
  // Neither leaves room: the plan fails naming each alternative and why.
  b.goal.write(encodeCartesianPath({room(at_needle), room(probeDown(-0.04, 0.05, 0.2))}));
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_failed"}));
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"), "none of the 2 goal alternatives can be taken from");
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"), "; goal 2 of 2 first (");

  // Joints of the wrong size are refused naming the ports.
  isur_joints.write(KDL::JntArray(7));
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_failed"}));
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"),
                  "ports isurMeasJoints/UR5MeasJoints: the scene's robots need isurMeasJoints 8 joints, UR5MeasJoints 6 "
                  "joints (got 7, 6)");
}

TEST(MotionPlannerComponent, FailuresAreEventsWithTheReason) {
  Bench b;
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_failed"}));
  EXPECT_EQ(b.planner.call<std::string>("lastPlanResult"),
            "no measured pose on port isurMeasPose: the start state is unknown");

  b.measure(kNeedle, kProbeStart);
  b.goal.write(encodeCartesianPath({{needleDown(0.0, 0.0, 0.06), kProbeGoal}}));  // needle in the phantom
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_failed"}));
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"),
                  "invalid goal: goal state is not valid: too close: micro/environment");
  // The message gives the query: start (the measured poses) and goal, needle first.
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"), " m; ");
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"), "; from first (");
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"), ") to first (");

  b.goal.write(encodeCartesianPath({{kNeedle, probeDown(0.25, 0.0, 0.9)}}));  // out of the probe's bounds
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_failed"}));
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"), "out of bounds: goal position of the probe (0.2500, 0.0000, 0.9000) m is outside the planner's bounds");

  KDL::Frame nan_probe = kProbeGoal;
  nan_probe.p.x(std::nan(""));
  b.goal.write(encodeCartesianPath({{kNeedle, kProbeGoal, kNeedle, kProbeGoal, kNeedle, kProbeGoal}}));
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_failed"}));
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"),
                  "port goalPoses: a waypoint holds 42 values; give 14 per goal alternative (the two goal poses) or "
                  "28 + 28 per motion to make room for");

  // A second pair is the straight motion after the goal: the probe then going over to the
  // needle fails at plan time, naming where it goes and why; staying at the goal is fine.
  b.goal.write(encodeCartesianPath({{kNeedle, kProbeGoal, kNeedle, probeDown(0.0, 0.0, 0.25)}}));
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_failed"}));
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"),
                  "invalid goal: the straight motion after the goal, to (0.0000, 0.0000, 0.2000) m and (0.0000, "
                  "0.0000, 0.2500) m, cannot be made: too close: micro/ur5");
  b.goal.write(encodeCartesianPath({{kNeedle, kProbeGoal, kNeedle, kProbeGoal}}));
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_done"}));
  // The needle going down into the phantom after the goal is the scene's primitive contact (the
  // insertion): allowed along the motion after the goal, never as a planned state (above).
  KDL::Frame needle_down = kNeedle;
  needle_down.p.z(0.06);
  b.goal.write(encodeCartesianPath({{kNeedle, kProbeGoal, needle_down, kProbeGoal}}));
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_done"}))
      << b.planner.call<std::string>("lastPlanResult");

  // Goal alternatives, the preferred first: the first that can be reached is taken, and the
  // result says which and why the ones before it were not.
  b.goal.write(encodeCartesianPath({{needleDown(0.0, 0.0, 0.06), kProbeGoal}, {kNeedle, kProbeGoal}}));
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_done"}));
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"),
                  "; goal 2 of 2 (goal 1 of 2 first (0.0000, 0.0000, 0.0600 m;");
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"), "invalid goal: goal state is not valid: too close");
  b.goal.write(encodeCartesianPath({{needleDown(0.0, 0.0, 0.06), kProbeGoal}, {needleDown(0.02, 0.0, 0.06), kProbeGoal}}));
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_failed"}));
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"), "none of the 2 goal alternatives can be taken from first (");
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"), "; goal 2 of 2 first (0.0200, 0.0000, 0.0600 m;");
  // Room for a later motion is checked from the measured joints, which this bench does not give.
  b.goal.write(encodeCartesianPath({{kNeedle, kProbeGoal, kNeedle, kProbeGoal, kNeedle, kProbeStart, kNeedle, kProbeGoal}}));
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_failed"}));
  EXPECT_EQ(b.planner.call<std::string>("lastPlanResult"),
            "the goal asks for room for a later motion, which is checked from the measured joints: connect ports "
            "isurMeasJoints and UR5MeasJoints");

  b.isur.write(nan_probe);
  b.goal.write(encodeCartesianPath({{kNeedle, kProbeGoal}}));
  b.clock.advance(1ms);
  b.planner.call<void>("askPlan");
  b.clock.advance(1ms);
  EXPECT_EQ(b.takeEvents(b.events), (std::vector<std::string>{"e_plan_failed"}));
  EXPECT_CONTAINS(b.planner.call<std::string>("lastPlanResult"), "invalid input: start pose has a NaN");
}

TEST(MotionPlannerComponent, CheckDistancePosesGivesTheMinimumDistance) {
  Bench b;
  const double free = b.planner.call<double>("checkDistancePoses", kNeedle, kProbeStart);
  EXPECT_GT(free, 0.005);
  EXPECT_EQ(b.planner.call<double>("checkDistancePoses", needleDown(0.05, 0.0, 0.05), kProbeStart), 0.0);
  EXPECT_TRUE(std::isnan(b.planner.call<double>("checkDistancePoses", needleDown(0.0, 0.0, -0.3), kProbeStart)));
}

TEST(MotionPlannerComponent, BadPropertiesAreRefusedNamingComponentAndProperty) {
  const auto refusal = [](const std::function<void(core::Component&)>& set) {
    MotionPlannerComponent planner("Planner");
    configureScene(planner);
    set(planner);
    const core::Result result = planner.configure();
    EXPECT_FALSE(result);
    return result.message;
  };
  EXPECT_CONTAINS(refusal([](core::Component& c) { c.setProperty("scene_file", std::string("absent.scene")); }),
                  "component 'Planner': property scene_file:");
  EXPECT_CONTAINS(refusal([](core::Component& c) { c.setProperty("scene_file", std::string("absent.scene")); }),
                  "absent.scene");
  EXPECT_CONTAINS(refusal([](core::Component& c) { c.setProperty("scene_file", std::string()); }),
                  "component 'Planner': property scene_file is empty");
  EXPECT_CONTAINS(refusal([](core::Component& c) { c.setProperty("planner", std::string("BIT*")); }),
                  "component 'Planner': property planner is 'BIT*': use RRTConnect, RRT, PRM, BiTRRT, LazyPRM, LBKPIECE1, BITstar");
  EXPECT_CONTAINS(refusal([](core::Component& c) { c.setProperty("env_mesh_names", std::string("table.stl")); }),
                  "property env_mesh_names: mesh file '" + scenes() + "/table.stl' does not exist");
  const std::string data = (std::filesystem::path(COBRA_SOURCE_DIR) / "planning/test/data").string();
  EXPECT_CONTAINS(refusal([&](core::Component& c) {
                    c.setProperty("env_mesh_names", std::string("- ") + data + "/malformed.stl");
                  }),
                  "property env_mesh_names:");
  EXPECT_CONTAINS(refusal([&](core::Component& c) {
                    c.setProperty("env_mesh_names", std::string("- ") + data + "/malformed.stl");
                  }),
                  "malformed.stl");
  EXPECT_CONTAINS(refusal([](core::Component& c) { c.setProperty("second_bounds_low", std::vector<double>{0.0}); }),
                  "properties second_bounds_low/_high need 3 values each");
  EXPECT_CONTAINS(refusal([](core::Component& c) { c.setProperty("macro_link_list", std::vector<double>{0.5}); }),
                  "property macro_link_list: 0.5");
}

TEST(MotionPlannerComponent, ThesisListsOverrideTheScene) {
  PlanningSceneSettings s;
  s.models_folder = scenes();
  s.scene_file = "puncturing.scene";
  const std::string data = (std::filesystem::path(COBRA_SOURCE_DIR) / "planning/test/data").string();
  s.env_mesh_names = "- " + data + "/unit_cube.stl";  // the phantom becomes a mesh
  s.macro_link_list = {0, 1, 2};                        // the micro yaw moves to the macro group
  s.ur5_link_list = {0, 1, 2, 3, 7};                    // wrists left out
  s.phantom_pose = KDL::Frame(KDL::Vector(0.1, 0.0, 0.0));
  s.min_collision_distance = 0.01;
  const planning::SceneDescription scene = buildPlanningScene(s);
  EXPECT_EQ(scene.min_collision_distance, 0.01);
  for (const auto& o : scene.objects) {
    if (o.name == "phantom") {
      EXPECT_EQ(o.shape.kind, planning::ShapeKind::Mesh);
      EXPECT_NEAR(o.offset.p.x(), 0.1, 1e-12);
      EXPECT_NEAR(o.offset.p.z(), 0.05, 1e-12);
    }
    if (o.name == "micro_yaw") {
      EXPECT_EQ(o.group, "macro");
    }
    EXPECT_NE(o.name, "ur5_wrist_1");
  }
  s.micro_link_list = {2};
  EXPECT_CONTAINS(test_support::messageOf([&] { buildPlanningScene(s); }),
                  "property micro_link_list: link 2 is also in macro_link_list");
}

TEST(MotionPlannerComponent, ToolFramesLetTheApplicationNameItsOwnToolFrames) {
  // An application whose needle frame has z along the needle (the I-SUR model's needle is x):
  // first_tool_frame = RotY(90°) makes its pose plan like the model's own.
  PlanningSceneSettings s;
  s.models_folder = scenes();
  s.scene_file = "puncturing.scene";
  s.first_tool_frame = KDL::Frame(KDL::Rotation::RotY(kPi / 2));
  const planning::SceneDescription scene = buildPlanningScene(s);
  EXPECT_TRUE(KDL::Equal(scene.robots[scene.robotIndex("isur")].toolFrame(0), s.first_tool_frame, 1e-15));
  EXPECT_TRUE(KDL::Equal(scene.robots[scene.robotIndex("ur5")].toolFrame(0), KDL::Frame::Identity(), 1e-15));

  auto configured = [&](MotionPlannerComponent& planner, bool app) {
    configureScene(planner);
    if (app) planner.setProperty("first_tool_frame", s.first_tool_frame);
    EXPECT_TRUE(planner.configure());
  };
  MotionPlannerComponent model_convention{"ModelPlanner"}, app_convention{"AppPlanner"};
  configured(model_convention, false);
  configured(app_convention, true);
  const KDL::Frame needle_z_along = kNeedle * s.first_tool_frame;  // the same physical needle
  const double expected = model_convention.call<double>("checkDistancePoses", kNeedle, kProbeStart);
  ASSERT_TRUE(std::isfinite(expected));
  EXPECT_NEAR(app_convention.call<double>("checkDistancePoses", needle_z_along, kProbeStart), expected, 1e-9);
  const double other = model_convention.call<double>("checkDistancePoses", needle_z_along, kProbeStart);
  EXPECT_TRUE(std::isnan(other) || std::abs(other - expected) > 1e-4) << "without it the rotated pose is another needle";
}

TEST(MotionPlannerComponent, EachToolOfTheTwoArmedRobotTakesTheFrameOfItsPoseOfQ) {
  // The suturing scene's I-SUR takes both poses of q with one solver: the first pose names the
  // Endo Stitch datum (first_tool_frame), the second the tip of the stick on the gripper
  // (second_tool_frame), each in its own tool's model frame.
  PlanningSceneSettings model_settings;
  model_settings.models_folder = scenes();
  model_settings.scene_file = "suturing.scene";
  PlanningSceneSettings app_settings = model_settings;
  app_settings.first_tool_frame = KDL::Frame(KDL::Rotation::RPY(kPi, -1.2, 0.0));
  app_settings.second_tool_frame = KDL::Frame(KDL::Rotation::RotY(-0.6), KDL::Vector(0.0, 0.0, 0.15));
  const planning::SceneDescription scene = buildPlanningScene(app_settings);
  ASSERT_EQ(scene.robots.size(), 1u);
  EXPECT_TRUE(KDL::Equal(scene.robots[0].toolFrame(0), app_settings.first_tool_frame, 1e-15));
  EXPECT_TRUE(KDL::Equal(scene.robots[0].toolFrame(1), app_settings.second_tool_frame, 1e-15));

  const planning::SceneDescription model_scene = buildPlanningScene(model_settings);
  planning::StateValidator model_frames(model_scene, planning::makeRobotModels(model_scene));
  planning::StateValidator app_frames(scene, planning::makeRobotModels(scene));
  // The suturing application's initial joints (apps/suturing/deployment/world.lua).
  const std::vector<double> q{0.0997079, 0.0995231, 0.0998925, 0, 0, 0.75, 0.45, 0,
                              -0.0755758, 1.01212, -0.823385, 0.541061, -0.755379, 0.171985};
  planning::DualPose model_poses, app_poses;
  ASSERT_TRUE(model_frames.toolPoses(q, model_poses));
  ASSERT_TRUE(app_frames.toolPoses(q, app_poses));
  EXPECT_TRUE(KDL::Equal(app_poses.first, model_poses.first * app_settings.first_tool_frame, 1e-12));
  EXPECT_TRUE(KDL::Equal(app_poses.second, model_poses.second * app_settings.second_tool_frame, 1e-12));
  // The same physical state through either convention's poses: the same clearance.
  const double expected = model_frames.minimumDistance(model_poses);
  ASSERT_TRUE(std::isfinite(expected));
  EXPECT_NEAR(app_frames.minimumDistance(app_poses), expected, 1e-9);
  const double other = model_frames.minimumDistance(app_poses);
  EXPECT_TRUE(std::isnan(other) || std::abs(other - expected) > 1e-4) << "the stick's tip is not the gripper";
}

// The measured state's clearance is measured every clearance_period (10 ms) from the joints
// written last: 45 steps of a seeded random walk of both robots' joints (the poses written with
// them trigger the planner every step) give one minDistance sample every 10 ms, each equal to
// what a separate validator measures at the joints of that step, not of an earlier one.
TEST(MotionPlannerComponent, ClearanceIsMeasuredEveryPeriodFromTheLatestJoints) {
  Bench b;
  core::OutputPort<KDL::JntArray> isur_joints{"isurJoints", "", "m, rad"};
  core::OutputPort<KDL::JntArray> ur5_joints{"ur5Joints", "", "rad"};
  core::connectPorts(isur_joints, b.planner.port("isurMeasJoints"));
  core::connectPorts(ur5_joints, b.planner.port("UR5MeasJoints"));
  core::InputPort<double> primitive{"primitive", "", "m"};  // the needle to the phantom: the I-SUR's
  core::connectPorts(b.planner.port("primitiveContactDistance"), primitive);
  planning::StateValidator reference(planning::loadScene(scenes() + "/puncturing.scene"),
                                     {{"isur", std::make_shared<planning::IsurPuncturingModel>()},
                                      {"ur5", std::make_shared<planning::Ur5Model>()}});
  KDL::JntArray isur(8), ur5(6);
  const double isur_q[8] = {0.00202, 0.00249, 0.204398, 0, 0, 0.85, 0.55, 0};
  const double ur5_q[6] = {0.798, -1.4495, -1.714, 1.5925, -1.571, -2.344};
  for (unsigned j = 0; j < 8; ++j) isur(j) = isur_q[j];
  for (unsigned j = 0; j < 6; ++j) ur5(j) = ur5_q[j];
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> step(-0.002, 0.002);
  std::vector<int> sampled_at;
  for (int ms = 0; ms < 45; ++ms) {
    for (unsigned j = 0; j < 8; ++j) isur(j) += j < 3 ? std::abs(step(rng)) : step(rng);  // sliders: from 0 up
    if (ms % 4 == 0)
      for (unsigned j = 0; j < 6; ++j) ur5(j) += step(rng);  // the UR5 holds still in between
    isur_joints.write(isur);
    ur5_joints.write(ur5);
    b.measure(needleDown(0.0, 0.0, 0.2), probeDown(-0.1, 0.0, 0.12));  // triggers the planner
    b.clock.advance(1ms);
    double clearance = 0.0;
    if (b.min_distance.read(clearance) != core::FlowStatus::NewData) continue;
    sampled_at.push_back(ms);
    std::vector<double> q(isur.data.data(), isur.data.data() + 8);
    q.insert(q.end(), ur5.data.data(), ur5.data.data() + 6);
    const planning::StateValidator::Distances expected = reference.distancesAt(q);
    ASSERT_FALSE(std::isnan(expected.clearance)) << "at " << ms << " ms: the walk left the joint limits";
    EXPECT_NEAR(clearance, expected.clearance, 1e-9) << "at " << ms << " ms";
    double needle_to_phantom = 0.0;
    ASSERT_EQ(primitive.read(needle_to_phantom), core::FlowStatus::NewData);
    EXPECT_EQ(needle_to_phantom, expected.primitive_contact) << "at " << ms << " ms";
  }
  EXPECT_EQ(sampled_at, (std::vector<int>{0, 10, 20, 30, 40}));
}

// Nobody reading the clearance: none is measured (the probe's planner in the puncturing app);
// connected later, its first sample comes within one clearance_period (10 ms).
TEST(MotionPlannerComponent, TheClearanceIsMeasuredOnlyWhileItsPortsAreRead) {
  Bench b;
  b.min_distance.disconnect();
  for (int ms = 0; ms < 25; ++ms) {
    b.measure(needleDown(0.0, 0.0, 0.2), probeDown(-0.1, 0.0, 0.12));
    b.clock.advance(1ms);
  }
  core::connectPorts(b.planner.port("minDistance"), b.min_distance);
  int first = -1;
  for (int ms = 0; ms < 12 && first < 0; ++ms) {
    b.measure(needleDown(0.0, 0.0, 0.2), probeDown(-0.1, 0.0, 0.12));
    b.clock.advance(1ms);
    double clearance = 0.0;
    if (b.min_distance.read(clearance) == core::FlowStatus::NewData) first = ms;
  }
  EXPECT_GE(first, 0) << "no clearance sample within 12 ms of connecting";
  EXPECT_LE(first, 10);
}

// On the wall clock run time begins at the executor's first tick; an own-pace planner may have
// measured before it, while the deployment loaded, on an earlier run's time. Its next step, at a
// run time earlier than that measurement, measures at once (it waited for the old time again).
TEST(MotionPlannerComponent, WhenRunTimeBeginsAgainTheClearanceIsMeasuredAtOnce) {
  MotionPlannerComponent planner("Planner");  // its own activity's time: run time (core::runEpoch)
  configureScene(planner);
  core::OutputPort<KDL::Frame> isur{"isur", "", "m"}, ur5{"ur5", "", "m"};
  core::InputPort<double> min_distance{"minDistance", "", "m"};
  core::connectPorts(isur, planner.port("isurMeasPose"));
  core::connectPorts(ur5, planner.port("UR5MeasPose"));
  core::connectPorts(planner.port("minDistance"), min_distance);
  ASSERT_TRUE(planner.configure());
  ASSERT_TRUE(planner.start());
  auto& activity = dynamic_cast<core::SlaveActivity&>(planner.activity());
  const auto step = [&] {
    isur.write(needleDown(0.0, 0.0, 0.2));
    ur5.write(probeDown(-0.1, 0.0, 0.12));
    activity.step();
  };
  double clearance = 0.0;
  step();
  ASSERT_EQ(min_distance.read(clearance), core::FlowStatus::NewData);
  const std::chrono::nanoseconds epoch = core::runEpoch();
  core::setRunEpoch(epoch + 10s);  // run time begins again: 10 s earlier than the measurement
  step();
  const core::FlowStatus after = min_distance.read(clearance);
  core::setRunEpoch(epoch);
  EXPECT_EQ(after, core::FlowStatus::NewData) << "the first step of the new run time measures";
  EXPECT_GT(clearance, 0.005);
}

TEST(MotionPlannerComponent, StartRefusesAPeriodicActivity) {
  MotionPlannerComponent planner("Planner");
  configureScene(planner);
  core::LockstepClock clock;
  clock.add(planner, 1ms);
  ASSERT_TRUE(planner.configure());
  const core::Result result = planner.start();
  EXPECT_FALSE(result);
  EXPECT_CONTAINS(result.message, "give this component a non-periodic, non-real-time activity");
}

}  // namespace
}  // namespace cobra::components
