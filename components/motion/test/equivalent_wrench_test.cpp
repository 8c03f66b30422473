// The Equivalent Wrench component (thesis §6.2.3) against the textbook adjoint, on the lockstep clock.
#include "cobra/components/motion/equivalent_wrench.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "cobra/core/core.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

struct Rig {
  EquivalentWrench component{"EqWrench"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Wrench> sensor{"sensor", "", "N"};
  core::OutputPort<KDL::Frame> frame{"frame", "", "m"};
  core::InputPort<KDL::Wrench> out{"out", "", "N"};
  Rig() {
    clock.add(component, 0ns);
    core::connectPorts(sensor, component.port("inWrench"));
    core::connectPorts(frame, component.port("referenceFrame"));
    core::connectPorts(component.port("outWrench"), out);
  }
  KDL::Wrench apply(const KDL::Wrench& w) {
    sensor.write(w);
    clock.advance(1ms);
    KDL::Wrench result;
    EXPECT_EQ(out.read(result), core::FlowStatus::NewData);
    return result;
  }
};

// f_c = Rᵀ f_b, τ_c = Rᵀ (τ_b − p × f_b), written out by hand for R = RotZ(90°), p = (0, 0, 0.1).
TEST(EquivalentWrench, MovesTheWrenchToTheToolTipFromThePropertyThenThePort) {
  Rig rig;
  const KDL::Frame tip(KDL::Rotation::RotZ(std::numbers::pi / 2), KDL::Vector(0, 0, 0.1));
  rig.component.setProperty("reference_frame", tip);
  ASSERT_TRUE(rig.component.configure());
  ASSERT_TRUE(rig.component.start());
  const KDL::Wrench measured(KDL::Vector(1, 0, 0), KDL::Vector(0, 0, 0));
  // p × f = (0, 0, 0.1) × (1, 0, 0) = (0, 0.1, 0); τ_b − p × f = (0, −0.1, 0); Rᵀ rotates by −90° about z.
  EXPECT_TRUE(KDL::Equal(rig.apply(measured), KDL::Wrench(KDL::Vector(0, -1, 0), KDL::Vector(-0.1, 0, 0)), 1e-12));

  rig.component.setProperty("change_reference_system", false);
  EXPECT_TRUE(KDL::Equal(rig.apply(measured), KDL::Wrench(KDL::Vector(1, 0, 0), KDL::Vector(0, -0.1, 0)), 1e-12));

  rig.frame.write(KDL::Frame(KDL::Vector(0, 0, 0.2)));  // the port now gives the frame
  EXPECT_TRUE(KDL::Equal(rig.apply(measured), KDL::Wrench(KDL::Vector(1, 0, 0), KDL::Vector(0, -0.2, 0)), 1e-12));

  rig.component.setProperty("change_application_point", false);
  EXPECT_TRUE(KDL::Equal(rig.apply(measured), measured, 1e-12));
}

// A tool-frame sensor wrench into base axes at the tool point, from the measured tool pose: the
// tool's x axis is the base's y axis (RotZ(90°)), so a push along tool x is a push along base y.
TEST(EquivalentWrench, InvertedReferenceTurnsAToolFrameWrenchIntoBaseAxes) {
  Rig rig;
  rig.component.setProperty("invert_reference", true);
  rig.component.setProperty("change_application_point", false);
  ASSERT_TRUE(rig.component.configure());
  ASSERT_TRUE(rig.component.start());
  rig.frame.write(KDL::Frame(KDL::Rotation::RotZ(std::numbers::pi / 2), KDL::Vector(0.4, 0, 0.3)));
  const KDL::Wrench in_tool(KDL::Vector(2, 0, 0), KDL::Vector(0, 0, 0.5));
  EXPECT_TRUE(KDL::Equal(rig.apply(in_tool), KDL::Wrench(KDL::Vector(0, 2, 0), KDL::Vector(0, 0, 0.5)), 1e-12));
}

}  // namespace
}  // namespace cobra::components
