// The control package's components on the lockstep clock, deployed and configured by the Lua
// deployer with named configurations (test/configurations/: copies of the puncturing and suturing
// applications' admittance configurations as they were when the applications took them over).
#include <gtest/gtest.h>

#include <limits>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/components/control/package.hpp"
#include "cobra/components/control/variable_admittance_component.hpp"
#include "cobra/core/fault_injection.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

struct Deployed {
  deploy::Configurator configurator;
  script::LuaState lua;
  deploy::LuaDeployer deployer{configurator, lua};
  core::OutputPort<KDL::Frame> reference{"reference", "", "m"};
  core::OutputPort<KDL::Wrench> wrench{"wrench", "", "N"};
  core::InputPort<KDL::Frame> pose{"pose", "", "m"};
  core::InputPort<double> tank{"tank", "", "J"};

  explicit Deployed(const std::string& task) {
    addBuiltinPackages(configurator.packages());
    deployer.run("initConfigurator({ 'cobra_control' }, { { peer_name = 'Admittance', component_type = 'VariableAdmittance' } }, '" +
                     std::string(COBRA_SOURCE_DIR) + "/components/control/test/configurations/" + task + "')\n"
                     "setActivities({ { peer_name = 'Admittance', period = 0.001 } })",
                 "deploy.lua");
    core::Component& a = configurator.getReferences().get("Admittance");
    core::connectPorts(reference, a.port("refPose"));
    core::connectPorts(wrench, a.port("measWrench"));
    core::connectPorts(a.port("admPose"), pose);
    core::connectPorts(a.port("tankEnergy"), tank);
    deployer.run("configureComponents({ 'Admittance' }) startComponents({ 'Admittance' })", "start.lua");
  }
  KDL::Frame run(std::chrono::milliseconds d, const KDL::Wrench& w, const KDL::Frame& ref = KDL::Frame::Identity()) {
    for (auto t = 0ms; t < d; t += 1ms) {
      reference.write(ref);
      wrench.write(w);
      configurator.clock().advance(1ms);
    }
    KDL::Frame p;
    (void)pose.read(p);
    return p;
  }
};

TEST(ControlComponents, AdmittanceFollowsItsConfigurationsWithoutJumps) {
  Deployed d("puncturing");
  EXPECT_EQ(d.configurator.deploymentSet().configurationNames(),
            (std::vector<std::string>{"free_motion", "needle_insertion", "penetration"}));
  d.deployer.run("applyConfiguration('free_motion')", "task.lua");
  const KDL::Wrench push(KDL::Vector(6.0, 0, 3.0), KDL::Vector::Zero());
  KDL::Frame p = d.run(3000ms, push);
  EXPECT_NEAR(p.p.x(), 6.0 / 1000.0, 1e-6);  // F/K with free_motion's (compliant) stiffness
  d.deployer.run("applyConfiguration('needle_insertion')", "task.lua");
  const KDL::Frame before = p;
  p = d.run(1ms, push);
  EXPECT_LT((p.p - before.p).Norm(), 1e-4);  // no jump when the configuration changes
  p = d.run(5000ms, push);
  EXPECT_NEAR(p.p.x(), 6.0 / 3000.0, 1e-5);  // stiff sideways now: the needle keeps its line
  EXPECT_NEAR(p.p.z(), 3.0 / 1000.0, 1e-5);  // compliant along the needle
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { d.run(100ms, push); }), 0);  // updateHook allocates nothing
  double energy = 0.0;
  ASSERT_NE(d.tank.read(energy), core::FlowStatus::NoData);
  EXPECT_GE(energy, 1.0);
}

TEST(ControlComponents, AReferenceJumpIsRebasedSoTheCommandedPoseStaysContinuous) {
  Deployed d("puncturing");
  core::InputPort<core::Event> events{"events", "", ""};
  core::connectPorts(d.configurator.getReferences().get("Admittance").port("events"), events,
                     core::ConnPolicy::buffer(16));
  d.deployer.run("applyConfiguration('penetration')", "task.lua");
  const KDL::Wrench skin(KDL::Vector(0, 0, 6.0), KDL::Vector::Zero());  // N: the skin pushes back
  KDL::Frame before = d.run(3000ms, skin);
  EXPECT_NEAR(before.p.z(), 6.0 / 4000.0, 1e-6);
  // A reference moving at 0.04 m/s (a trajectory) is followed, not rebased.
  KDL::Frame ref = KDL::Frame::Identity();
  for (int i = 0; i < 100; ++i) {
    ref.p.x(ref.p.x() + 4e-5);
    d.run(1ms, skin, ref);
  }
  core::Event e;
  EXPECT_EQ(events.read(e), core::FlowStatus::NoData);
  // A new trajectory starting at the measured pose, 1.5 mm above the old reference.
  before = d.run(1ms, skin, ref);
  KDL::Frame jumped = ref;
  jumped.p.z(ref.p.z() + 1.5e-3);
  const KDL::Frame after = d.run(1ms, skin, jumped);
  EXPECT_LT((after.p - before.p).Norm(), 1e-4);  // m: not the 1.5 mm jump
  ASSERT_EQ(events.read(e), core::FlowStatus::NewData);
  EXPECT_EQ(e.name.str(), "e_reference_jump");
  const KDL::Frame settled = d.run(5000ms, skin, jumped);
  EXPECT_NEAR(settled.p.z(), jumped.p.z() + 6.0 / 4000.0, 1e-5);  // the new reference's equilibrium
  // Turning at 2 rad/s (2 mrad per 1 ms step, below max_reference_angular_speed 3 rad/s) is
  // followed; a 0.2 rad turn within one step is a jump.
  KDL::Frame turning = jumped;
  for (int i = 0; i < 20; ++i) {
    turning.M = KDL::Rotation::RotZ(0.002) * turning.M;
    d.run(1ms, skin, turning);
  }
  EXPECT_EQ(events.readNew(e), core::FlowStatus::OldData);
  turning.M = KDL::Rotation::RotZ(0.2) * turning.M;
  d.run(1ms, skin, turning);
  ASSERT_EQ(events.readNew(e), core::FlowStatus::NewData);
  EXPECT_EQ(e.name.str(), "e_reference_jump");
}

// A silent force sensor: with wrench_timeout set, the admittance holds its pose instead of
// pushing on with the last (stale) force, says so once, and resumes from the held state.
TEST(ControlComponents, ABlindAdmittanceHoldsItsPoseUntilTheWrenchReturns) {
  Deployed d("puncturing");
  core::Component& a = d.configurator.getReferences().get("Admittance");
  core::InputPort<core::Event> events{"events", "", ""};
  core::connectPorts(a.port("events"), events, core::ConnPolicy::buffer(16));
  a.setProperty("wrench_timeout", 0.005);  // s: read each step
  d.deployer.run("applyConfiguration('free_motion')", "task.lua");
  const KDL::Wrench push(KDL::Vector(0, 0, 6.0), KDL::Vector::Zero());
  d.run(20ms, push);  // moving: far from its 6 mm equilibrium
  KDL::Frame moving_ref = KDL::Frame::Identity();
  KDL::Frame held;
  for (int i = 0; i < 300; ++i) {  // 0.3 s without a wrench sample; the reference moves on
    moving_ref.p.x(moving_ref.p.x() + 1e-5);
    d.reference.write(moving_ref);
    d.configurator.clock().advance(1ms);
    KDL::Frame p;
    (void)d.pose.read(p);
    if (i == 10) held = p;
    if (i > 10) {
      EXPECT_EQ(p, held) << i;  // not a micrometre: held, not driven by a stale force
    }
  }
  core::Event e;
  ASSERT_EQ(events.read(e), core::FlowStatus::NewData);
  EXPECT_EQ(e.name.str(), "e_wrench_lost");
  EXPECT_NE(events.read(e), core::FlowStatus::NewData) << e.name.str();  // once
  const KDL::Frame resumed = d.run(1ms, push, moving_ref);
  EXPECT_LT((resumed.p - held.p).Norm(), 1e-4);  // continuous from the held state
  ASSERT_EQ(events.read(e), core::FlowStatus::NewData);
  EXPECT_EQ(e.name.str(), "e_wrench_restored");
  EXPECT_NE(events.read(e), core::FlowStatus::NewData) << e.name.str();  // the moved reference is no jump
  a.setProperty("wrench_timeout", -1.0);
  EXPECT_TRUE(a.stop());
  EXPECT_TRUE(a.cleanup());
  EXPECT_EQ(a.configure().message,
            "component 'Admittance': property wrench_timeout is -1.000000 s; expected >= 0 s (0: never hold)");
}

// A broken sensor chain writes NaN, then inf: the admittance refuses the sample (it would carry
// into the controller's state and the robot's command), holds its last pose, says so once per
// episode, allocates nothing doing it, and resumes continuously on the next finite sample.
TEST(ControlComponents, ANonFiniteWrenchIsRefusedTheOutputHoldsAndTheEventIsEmittedOnce) {
  Deployed d("puncturing");
  core::Component& a = d.configurator.getReferences().get("Admittance");
  core::InputPort<core::Event> events{"events", "", ""};
  core::connectPorts(a.port("events"), events, core::ConnPolicy::buffer(16));
  EXPECT_EQ(a.call<std::string>("lastFailure"), "no non-finite input refused");
  d.deployer.run("applyConfiguration('free_motion')", "task.lua");
  const KDL::Wrench push(KDL::Vector(0, 0, 6.0), KDL::Vector::Zero());
  const KDL::Frame before = d.run(20ms, push);  // moving: far from its 6 mm equilibrium
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    const KDL::Wrench broken(KDL::Vector(0, 0, bad), KDL::Vector::Zero());
    KDL::Frame held;
    (void)d.pose.read(held);
    long allocations = 0;
    for (int i = 0; i < 200; ++i) {
      allocations += cobra::test_support::allocationsDuring([&] { d.run(1ms, broken); });
      KDL::Frame p;
      (void)d.pose.read(p);
      ASSERT_EQ(p, held) << i;  // not a micrometre, and finite
    }
    EXPECT_EQ(allocations, 0);
    core::Event e;
    ASSERT_EQ(events.read(e), core::FlowStatus::NewData);
    EXPECT_EQ(e.name.str(), "e_input_not_finite");
    EXPECT_NE(events.read(e), core::FlowStatus::NewData) << e.name.str();  // once per episode
    EXPECT_EQ(a.state(), core::State::Running);  // refused, not thrown
    const KDL::Frame resumed = d.run(1ms, push);
    EXPECT_LT((resumed.p - held.p).Norm(), 1e-4);  // continuous from the held state
    EXPECT_GT((resumed.p - before.p).Norm(), 0.0);
  }
  EXPECT_EQ(a.call<std::string>("lastFailure"),
            "at 0.221 s Admittance refused a non-finite measWrench sample; it holds its last admPose");
  const KDL::Frame settled = d.run(3000ms, push);
  EXPECT_NEAR(settled.p.z(), 6.0 / 1000.0, 1e-5);  // the controller's state was not poisoned
}

// The robot refused the admittance's commands and holds 3 mm behind its output: the output
// restarts at the held pose in that step, stays there while the reference's old sample is all
// there is (the trajectory generator stopped), and moves on continuously with the next one.
TEST(ControlComponents, AHeldPoseReSyncsTheOutputWhichStaysThereUntilANewReference) {
  Deployed d("puncturing");
  core::Component& a = d.configurator.getReferences().get("Admittance");
  core::OutputPort<KDL::Frame> held_port{"held", "", "m"};
  core::connectPorts(held_port, a.port("heldPose"));
  core::InputPort<KDL::Frame> held_reference{"heldReference", "", "m"};
  core::connectPorts(a.port("heldRefPose"), held_reference);
  core::InputPort<core::Event> events{"events", "", ""};
  core::connectPorts(a.port("events"), events, core::ConnPolicy::buffer(16));
  d.deployer.run("applyConfiguration('penetration')", "task.lua");
  const KDL::Wrench skin(KDL::Vector(0, 0, 6.0), KDL::Vector::Zero());  // N: the skin pushes back
  d.run(3000ms, skin);
  // Along x at 0.04 m/s: a motion.
  KDL::Frame ref = KDL::Frame::Identity();
  KDL::Frame p;
  for (int i = 0; i < 500; ++i) {
    ref.p.x(ref.p.x() + 4e-5);
    p = d.run(1ms, skin, ref);
  }
  const KDL::Frame held(p.M, p.p - KDL::Vector(0.003, 0, 0));
  held_port.write(held);
  d.wrench.write(skin);
  d.configurator.clock().advance(1ms);
  ASSERT_EQ(d.pose.read(p), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(p, held, 1e-12));  // the command is the held pose in the re-sync's step
  core::Event e;
  ASSERT_EQ(events.read(e), core::FlowStatus::NewData);
  EXPECT_EQ(e.name.str(), "e_resynced");
  // The reference it steps about: the held pose less the skin's compression (6 N at 4000 N/m).
  KDL::Frame reference;
  ASSERT_EQ(held_reference.read(reference), core::FlowStatus::NewData);
  EXPECT_NEAR(reference.p.z(), held.p.z() - 6.0 / 4000.0, 1e-9);
  EXPECT_NEAR(reference.p.x(), held.p.x(), 1e-9);
  // The reference's last sample (0 ms old, 3 mm ahead) is not followed: the output stays, in
  // equilibrium with the skin's force, and every step allocates nothing.
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              for (int i = 0; i < 1000; ++i) {
                d.wrench.write(skin);
                d.configurator.clock().advance(1ms);
                (void)d.pose.read(p);
                if ((p.p - held.p).Norm() > 1e-5) break;
              }
            }),
            0);
  EXPECT_LT((p.p - held.p).Norm(), 1e-5) << "m: the output left the held pose";
  // Re-synced again while held (a robot refusing step after step): allocation-free as well.
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              held_port.write(held);
              d.wrench.write(skin);
              d.configurator.clock().advance(1ms);
            }),
            0);
  // A new reference sample (the trajectory generator, re-synced to heldRefPose, starts a motion
  // from there): followed continuously.
  KDL::Frame next = reference;
  KDL::Frame before = p;
  for (int i = 0; i < 200; ++i) {
    next.p.y(next.p.y() + 4e-5);
    p = d.run(1ms, skin, next);
    ASSERT_LT((p.p - before.p).Norm(), 1e-4) << "step " << i;
    before = p;
  }
  EXPECT_GT(p.p.y() - held.p.y(), 0.005);  // m: it moved on with the reference
}

// The admittance holding on a failure (a non-finite wrench refused; a hook that threw) tells the
// producer of its reference (heldRefPose, the trajectory generator's heldPose_i) where the
// reference of its last output was, so that the producer's motion, all of its arms, ends there
// with this arm: each step of a non-finite episode, and once on entering Exception.
TEST(ControlComponents, AnAdmittanceHoldingOnAFailureTellsItsReferencesProducerWhereItHolds) {
  Deployed d("puncturing");
  core::Component& a = d.configurator.getReferences().get("Admittance");
  core::InputPort<KDL::Frame> held_reference{"heldReference", "", "m"};
  core::connectPorts(a.port("heldRefPose"), held_reference);
  d.deployer.run("applyConfiguration('free_motion')", "task.lua");
  const KDL::Wrench none = KDL::Wrench::Zero();
  KDL::Frame ref = KDL::Frame::Identity();
  const auto move = [&](int steps, const KDL::Wrench& w) {  // along x at 0.04 m/s
    for (int i = 0; i < steps; ++i) {
      ref.p.x(ref.p.x() + 4e-5);
      d.run(1ms, w, ref);
    }
  };
  move(100, none);
  KDL::Frame told;
  EXPECT_EQ(held_reference.read(told), core::FlowStatus::NoData);  // nothing held yet
  const KDL::Frame last_stepped = ref;
  const KDL::Wrench broken(KDL::Vector(std::numeric_limits<double>::quiet_NaN(), 0, 0), KDL::Vector::Zero());
  for (int i = 0; i < 5; ++i) {
    move(1, broken);  // the reference moves on; the output holds
    ASSERT_EQ(held_reference.read(told), core::FlowStatus::NewData) << "step " << i << " of the episode";
    EXPECT_TRUE(KDL::Equal(told, last_stepped, 1e-12)) << "the reference of the last output, not the moved-on one";
  }
  move(50, none);  // resumed
  EXPECT_EQ(held_reference.read(told), core::FlowStatus::OldData);  // not held any more: nothing new
  const KDL::Frame before_throw = ref;
  core::injectUpdateException(a, "a bug in the admittance");
  move(1, none);
  ASSERT_EQ(a.state(), core::State::Exception);
  ASSERT_EQ(held_reference.read(told), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(told, before_throw, 1e-12));
  move(10, none);
  EXPECT_EQ(held_reference.read(told), core::FlowStatus::OldData);  // told once: nothing steps any more
}

TEST(ControlComponents, SuturingConfigurationsLoadAndApply) {
  Deployed d("suturing");
  EXPECT_EQ(d.configurator.deploymentSet().configurationNames(), (std::vector<std::string>{"contact", "free_motion"}));
  d.deployer.run("applyConfiguration('contact')", "task.lua");
  const KDL::Frame p = d.run(5000ms, KDL::Wrench(KDL::Vector(2.0, 0, 0), KDL::Vector::Zero()));
  EXPECT_NEAR(p.p.x(), 2.0 / 3000.0, 1e-5);  // contact is the stiffer suturing configuration
  d.deployer.run("applyConfiguration('free_motion')", "task.lua");
  EXPECT_NEAR(d.run(5000ms, KDL::Wrench(KDL::Vector(2.0, 0, 0), KDL::Vector::Zero())).p.x(), 2.0 / 1000.0, 1e-5);
}

TEST(ControlComponents, BadMatricesAreRefusedAtConfigureWithTheirName) {
  VariableAdmittanceController a("Admittance");
  a.setProperty("stiffness", std::vector<double>{1, 2, 3});
  EXPECT_CONTAINS(a.configure().message, "property stiffness has 3 numbers; give 6 (the diagonal) or 36 (row-major)");
  a.setProperty("stiffness", std::vector<double>{10, 10, 10, 10, 10, 10});  // below constant_stiffness (50)
  EXPECT_CONTAINS(a.configure().message, "stiffness[0] = 10 N/m: must be >= constant_stiffness[0] = 50 N/m");
  VariableAdmittanceController b("Admittance");
  b.setProperty("max_reference_speed", 0.0);
  EXPECT_CONTAINS(b.configure().message, "properties max_reference_speed (0.000000 m/s) and "
                                         "max_reference_angular_speed (3.000000 rad/s) must be > 0");
}

}  // namespace
}  // namespace cobra::components
