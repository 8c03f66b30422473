// The Kinematics Solver component (thesis §6.2.4): data flow, on demand, interchangeable solvers,
// the continuity rule (a wrist flip and a jump refused with e_ik_discontinuity once; commands
// judged from the last accepted one while they stream, from the measured joints after a pause).
#include "cobra/components/motion/kinematics_solver_component.hpp"

#include <gtest/gtest.h>

#include "cobra/core/core.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

KDL::JntArray joints(std::initializer_list<double> values) {
  KDL::JntArray q(static_cast<unsigned>(values.size()));
  unsigned i = 0;
  for (double v : values) q(i++) = v;
  return q;
}

struct Rig {
  KinematicsSolverComponent solver{"IK"};
  core::LockstepClock clock;
  core::OutputPort<KDL::JntArray> measured{"measured", "", "rad"};
  core::OutputPort<KDL::Frame> desired{"desired", "", "m"};
  core::InputPort<KDL::Frame> pose{"pose", "", "m"};
  core::InputPort<KDL::JntArray> command{"command", "", "rad"};
  core::InputPort<core::Event> events{"events", "", ""};

  explicit Rig(const char* kind, const KDL::Frame& base = KDL::Frame::Identity()) {
    solver.setProperty("solver", std::string(kind));
    solver.setProperty("base_frame", base);
    clock.add(solver, 1ms);
    measured.setDataSample(KDL::JntArray(6));
    core::connectPorts(measured, solver.port("jointPositions"));
    core::connectPorts(desired, solver.port("desCartPose"));
    core::connectPorts(solver.port("cartPose"), pose);
    core::connectPorts(solver.port("desJointPositions"), command);
    core::connectPorts(solver.port("events"), events, core::ConnPolicy::buffer(8));
    EXPECT_TRUE(solver.configure());
    EXPECT_TRUE(solver.start());
  }
  std::vector<std::string> takeEvents() {
    std::vector<std::string> out;
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) out.push_back(e.name.str());
    return out;
  }
};

TEST(KinematicsSolverComponent, ForwardAndInverseByDataFlowWithEitherSolver) {
  const KDL::Frame base(KDL::Rotation::RotZ(0.3), KDL::Vector(0.1, -0.2, 0.05));
  for (const char* kind : {"closed_form", "kdl_lma", "kdl_nr"}) {
    SCOPED_TRACE(kind);
    Rig rig(kind, base);
    const KDL::JntArray q0 = joints({0.1, -1.0, 1.2, -0.4, 1.1, 0.2});
    rig.measured.write(q0);
    rig.clock.advance(1ms);
    KDL::Frame at_q0;
    ASSERT_EQ(rig.pose.read(at_q0), core::FlowStatus::NewData);
    EXPECT_TRUE(KDL::Equal(at_q0, rig.solver.call<KDL::Frame>("forward", q0), 1e-12));

    // 0.5 mm and 1 mrad: within one 1 ms period at 3.14 rad/s per joint.
    const KDL::Frame target = at_q0 * KDL::Frame(KDL::Rotation::RotX(0.001), KDL::Vector(0.0002, 0.0004, -0.0002));
    rig.desired.write(target);
    rig.clock.advance(1ms);
    KDL::JntArray q1;
    ASSERT_EQ(rig.command.read(q1), core::FlowStatus::NewData);
    EXPECT_TRUE(KDL::Equal(rig.solver.call<KDL::Frame>("forward", q1), target, 1e-8));
    EXPECT_LT((q1.data - q0.data).norm(), 0.01);  // the branch of the measured joints, not another one
  }
}

TEST(KinematicsSolverComponent, PublishesOnlyValidSolutionsAndSaysWhenItFails) {
  Rig rig("closed_form");
  rig.desired.write(KDL::Frame(KDL::Vector(3.0, 0, 0)));  // 3 m away: beyond the UR5's reach
  rig.desired.write(KDL::Frame(KDL::Vector(3.0, 1.0, 0)));
  rig.clock.advance(1ms);
  KDL::JntArray q;
  EXPECT_EQ(rig.command.read(q), core::FlowStatus::NoData);
  EXPECT_EQ(rig.solver.call<std::string>("lastIkStatus"), "unreachable");
  const KDL::Frame reachable = rig.solver.call<KDL::Frame>("forward", joints({0.2, -1.2, 1.0, -0.5, 1.0, 0.0}));
  rig.desired.write(reachable);
  rig.clock.advance(1ms);
  EXPECT_EQ(rig.command.read(q), core::FlowStatus::NewData);
  EXPECT_EQ(rig.takeEvents(), (std::vector<std::string>{"e_ik_failed", "e_ik_solved"}));
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] {
                    rig.solver.call<KDL::JntArray>("inverse", KDL::Frame(KDL::Vector(3, 0, 0)), joints({0, 0, 0, 0, 0, 0}));
                  }),
                  "inverse kinematics: unreachable");
}

TEST(KinematicsSolverComponent, RefusesConfigurationsItCannotBuild) {
  KinematicsSolverComponent c("IK");
  c.setProperty("robot", std::string("kuka"));
  EXPECT_CONTAINS(c.configure().message, "property robot is 'kuka'; expected ur5, puma260 or dh");
  c.setProperty("robot", std::string("dh"));
  c.setProperty("dh_table", std::vector<double>{0.3, 0, 0, 0, 0, -3, 3, 0.2, 0, 0});
  EXPECT_CONTAINS(c.configure().message, "property dh_table has 10 numbers; give 7 per joint");
  c.setProperty("dh_table", std::vector<double>{0.3, 0, 0, 0, 0, -3, 3, 0.2, 0, 0, 0, 0, -3, 3});
  EXPECT_CONTAINS(c.configure().message, "robot dh has no closed-form solver; set solver to kdl_nr or kdl_lma");
  c.setProperty("solver", std::string("kdl_lma"));
  EXPECT_EQ(c.configure().message,
            "component 'IK': property max_joint_velocity is empty: give one velocity limit per joint (rad/s, m/s) for "
            "robot dh (only ur5 has a default)");
  c.setProperty("max_joint_velocity", std::vector<double>{1.0, 1.0});
  EXPECT_CONTAINS(c.configure().message, "property period is 0 s and the activity has no period");
  c.setProperty("period", -0.01);
  EXPECT_CONTAINS(c.configure().message, "property period is -0.01 s: give a finite value >= 0");
  c.setProperty("period", 0.01);
  c.setProperty("max_joint_velocity", std::vector<double>{1.0, 0.0});
  EXPECT_CONTAINS(c.configure().message,
                  "property max_joint_velocity: IK: max_velocity of joint 2 is 0 rad/s: give a finite value > 0");
  c.setProperty("max_joint_velocity", std::vector<double>{1.0, 1.0});
  ASSERT_TRUE(c.configure());
  // A planar 2-link arm: q = (0, 0) puts the tool at x = 0.5 m.
  EXPECT_TRUE(KDL::Equal(c.call<KDL::Frame>("forward", joints({0, 0})).p, KDL::Vector(0.5, 0, 0), 1e-12));
  c.setProperty("solver", std::string("fastest"));
  EXPECT_CONTAINS(c.configure().message, "property solver: ");
}

TEST(KinematicsSolverComponent, AWristFlipIsRefusedOnceThenAnAcceptableCommandIsFollowed) {
  Rig rig("closed_form");
  // Wrist 0.01 rad from its singularity; the command's nearest joints have the wrist flipped.
  const KDL::JntArray q0 = joints({0.1, -1.3, 1.5, -1.7, 0.01, 0.3});
  KDL::JntArray across = q0;
  across(4) = -0.01;
  const KDL::Frame flipped = rig.solver.call<KDL::Frame>("forward", across);
  rig.measured.write(q0);
  for (int i = 0; i < 50; ++i) {
    rig.desired.write(flipped);
    rig.clock.advance(1ms);
  }
  KDL::JntArray q;
  EXPECT_EQ(rig.command.read(q), core::FlowStatus::NoData);
  EXPECT_EQ(rig.solver.call<std::string>("lastIkStatus"), "discontinuous");
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_ik_discontinuity"});
  KDL::JntArray nearby = q0;
  nearby(0) += 0.002;
  rig.desired.write(rig.solver.call<KDL::Frame>("forward", nearby));
  rig.clock.advance(1ms);
  ASSERT_EQ(rig.command.read(q), core::FlowStatus::NewData);
  for (unsigned j = 0; j < 6; ++j) EXPECT_NEAR(q(j), nearby(j), 1e-9);
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_ik_solved"});
}

TEST(KinematicsSolverComponent, StreamedCommandsAreJudgedFromTheLastOneAndAfterAPauseFromTheMeasuredJoints) {
  Rig rig("closed_form");
  rig.solver.setProperty("max_joint_velocity", std::vector<double>(6, 1.0));  // 1 mrad per 1 ms period
  ASSERT_TRUE(rig.solver.stop());
  ASSERT_TRUE(rig.solver.configure());
  ASSERT_TRUE(rig.solver.start());
  const KDL::JntArray q0 = joints({0.1, -1.0, 1.2, -0.4, 1.1, 0.2});
  rig.measured.write(q0);  // a lagging robot: its measured joints stay at q0
  // A ramp of 0.8 mrad per period on joint 1, 20 periods: 16 mrad ahead of the measured joints,
  // every command accepted since each is 0.8 mrad from the previous one.
  KDL::JntArray q = q0;
  KDL::JntArray out;
  for (int i = 1; i <= 20; ++i) {
    q(0) = q0(0) + 0.0008 * i;
    rig.desired.write(rig.solver.call<KDL::Frame>("forward", q));
    rig.clock.advance(1ms);
    ASSERT_EQ(rig.command.read(out), core::FlowStatus::NewData) << i;
  }
  EXPECT_NEAR(out(0), q0(0) + 0.016, 1e-9);
  // A pause: the next command is judged from the measured joints (q0), 16.8 mrad away: refused.
  rig.clock.advance(1ms);
  q(0) += 0.0008;
  rig.desired.write(rig.solver.call<KDL::Frame>("forward", q));
  rig.clock.advance(1ms);
  EXPECT_NE(rig.command.read(out), core::FlowStatus::NewData);
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_ik_discontinuity"});
}

// A refused command: heldCartPose is the pose of the last accepted solution (the robot's set-point),
// in each update that refuses, for the producers of the commands to re-sync to; a command from
// there is accepted. Joints held by something else (a drive's quick stop) become the reference of
// the next command and are passed on the same way. Neither allocates.
TEST(KinematicsSolverComponent, ARefusalOrAQuickStopPublishesTheHeldPose) {
  Rig rig("closed_form", KDL::Frame(KDL::Vector(0.1, 0, 0.2)));
  core::InputPort<KDL::Frame> held{"held", "", "m"};
  core::OutputPort<KDL::JntArray> stopped{"stopped", "", "rad"};
  core::connectPorts(rig.solver.port("heldCartPose"), held);
  core::connectPorts(stopped, rig.solver.port("heldJointPositions"));
  const KDL::JntArray q0 = joints({0.1, -1.0, 1.2, -0.4, 1.1, 0.2});
  KDL::JntArray q1 = q0;
  q1(0) += 0.002;
  rig.measured.write(q0);
  rig.desired.write(rig.solver.call<KDL::Frame>("forward", q0));
  rig.clock.advance(1ms);
  rig.desired.write(rig.solver.call<KDL::Frame>("forward", q1));
  rig.clock.advance(1ms);
  KDL::Frame f;
  EXPECT_EQ(held.read(f), core::FlowStatus::NoData);  // nothing refused yet
  KDL::JntArray jump = q1;
  jump(0) += 0.5;
  const KDL::Frame far = rig.solver.call<KDL::Frame>("forward", jump);
  rig.takeEvents();
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              rig.desired.write(far);
              rig.clock.advance(1ms);
            }),
            0);
  ASSERT_EQ(held.read(f), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(f, rig.solver.call<KDL::Frame>("forward", q1), 1e-12)) << "the last accepted solution";
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_ik_discontinuity"});
  rig.desired.write(f);  // the producers re-synced: their next command is the held pose
  rig.clock.advance(1ms);
  KDL::JntArray q;
  ASSERT_EQ(rig.command.read(q), core::FlowStatus::NewData);
  for (unsigned j = 0; j < 6; ++j) EXPECT_NEAR(q(j), q1(j), 1e-9);
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_ik_solved"});
  EXPECT_NE(held.read(f), core::FlowStatus::NewData);
  // The drives quick-stopped 20 mrad further on joint 2: the held pose is passed on, and a command
  // from the old set-point is now judged from the stopped joints.
  KDL::JntArray stop = q1;
  stop(1) += 0.02;
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              stopped.write(stop);
              rig.clock.advance(1ms);
            }),
            0);
  ASSERT_EQ(held.read(f), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(f, rig.solver.call<KDL::Frame>("forward", stop), 1e-12));
  rig.desired.write(rig.solver.call<KDL::Frame>("forward", q1));
  rig.clock.advance(1ms);
  EXPECT_NE(rig.command.read(q), core::FlowStatus::NewData);  // 20 mrad from where the robot is held
  EXPECT_EQ(rig.takeEvents(), std::vector<std::string>{"e_ik_discontinuity"});
}

TEST(KinematicsSolverComponent, TheDataFlowAllocatesNothingWithTheClosedForm) {
  Rig rig("closed_form");
  const KDL::JntArray q0 = joints({0.1, -1.0, 1.2, -0.4, 1.1, 0.2});
  const KDL::Frame target = rig.solver.call<KDL::Frame>("forward", q0);
  rig.measured.write(q0);
  rig.desired.write(target);
  rig.clock.advance(2ms);
  KDL::JntArray q(6);
  (void)rig.command.read(q);
  KDL::JntArray jump = q0;
  jump(0) += 0.5;
  const KDL::Frame far = rig.solver.call<KDL::Frame>("forward", jump);
  (void)rig.takeEvents();
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int i = 0; i < 100; ++i) {
                rig.measured.write(q0);
                rig.desired.write(i % 10 == 5 ? far : target);  // every 10th refused: events too
                rig.clock.advance(1ms);
                (void)rig.command.read(q);
              }
            }),
            0);
  EXPECT_EQ(rig.takeEvents().size(), 8u);  // the buffer's capacity (10 x refused, solved)
}

TEST(KinematicsSolverComponent, TheKdlAndClosedFormTypesAreInterchangeable) {
  KdlKinematicsSolver kdl("IK");
  ClosedFormKinematicsSolver closed("IK");
  EXPECT_EQ(kdl.getProperty<std::string>("solver"), "kdl_nr");
  EXPECT_EQ(closed.getProperty<std::string>("solver"), "closed_form");
  const core::ComponentInfo a = core::describe(kdl), b = core::describe(closed);
  ASSERT_EQ(a.ports.size(), b.ports.size());
  for (std::size_t i = 0; i < a.ports.size(); ++i) EXPECT_EQ(a.ports[i].name, b.ports[i].name);
  // Not run by an activity: the continuity rule's period comes from the property.
  kdl.setProperty("period", 0.001);
  closed.setProperty("period", 0.001);
  ASSERT_TRUE(kdl.configure());
  ASSERT_TRUE(closed.configure());
  const KDL::JntArray q = joints({0.4, -0.8, 1.0, 0.3, -0.9, 0.5});
  const KDL::Frame target = closed.call<KDL::Frame>("forward", q);
  EXPECT_TRUE(KDL::Equal(kdl.call<KDL::Frame>("forward", kdl.call<KDL::JntArray>("inverse", target, q)), target, 1e-9));
  EXPECT_TRUE(KDL::Equal(closed.call<KDL::Frame>("forward", closed.call<KDL::JntArray>("inverse", target, q)), target, 1e-9));
}

}  // namespace
}  // namespace cobra::components
