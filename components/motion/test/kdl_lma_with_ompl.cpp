// KDL's Levenberg-Marquardt solver in a process that loads Debian's OMPL before liborocos-kdl, as the
// `cobra` tool does (this executable is linked with libompl first on purpose: CMakeLists.txt). Both
// libraries export Eigen::JacobiSVD<MatrixXd> functions built against different Eigen versions and
// the dynamic linker binds KDL's calls to OMPL's copies (kinematics::kdlLmaConflict): before the
// check, the KdlKinematicsSolver's first inverse aborted this process in Eigen's matrixU assertion.
#include <gtest/gtest.h>

#include "cobra/components/motion/kinematics_solver_component.hpp"
#include "cobra/core/core.hpp"
#include "cobra/kinematics/puma260.hpp"
#include "cobra/kinematics/serial_chain.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

TEST(KdlLmaWithOmpl, TheConflictIsDetectedAndNamesBothLibraries) {
  const std::string conflict = kinematics::kdlLmaConflict();
  EXPECT_CONTAINS(conflict, "liborocos-kdl");
  EXPECT_CONTAINS(conflict, "libompl");
  EXPECT_CONTAINS(conflict, "JacobiSVD");
  try {
    (void)kinematics::makePuma260Solver(kinematics::SolverKind::KdlLevenbergMarquardt);
    ADD_FAILURE() << "a Levenberg-Marquardt solver was made although it would abort at its first solve";
  } catch (const std::invalid_argument& e) {
    EXPECT_CONTAINS(e.what(), "Puma 260: KDL's Levenberg-Marquardt solver");
    EXPECT_CONTAINS(e.what(), "use KDL's Newton-Raphson solver (kdl_nr) or the closed form");
  }
}

TEST(KdlLmaWithOmpl, TheKdlComponentSolvesByDefaultAndRefusesLmaAtConfigure) {
  core::LockstepClock clock;
  KdlKinematicsSolver ik("IK");
  clock.add(ik, 1ms);
  ik.setProperty("robot", std::string("puma260"));
  ik.setProperty("max_joint_velocity", std::vector<double>(6, 2.0));
  core::OutputPort<KDL::JntArray> measured{"measured", "", "rad"};
  core::OutputPort<KDL::Frame> desired{"desired", "", "m"};
  core::InputPort<KDL::JntArray> command{"command", "", "rad"};
  core::connectPorts(measured, ik.port("jointPositions"));
  core::connectPorts(desired, ik.port("desCartPose"));
  core::connectPorts(ik.port("desJointPositions"), command);
  // The Puma 260 task's first command (seed and target of the run that aborted).
  KDL::JntArray q(6);
  const double start[6] = {0.4677, 1.2117, -3.2805, -2.2e-6, -1.0727, -2.6740};
  for (unsigned i = 0; i < 6; ++i) q(i) = start[i];
  ASSERT_TRUE(ik.configure()) << ik.lastError();
  ASSERT_TRUE(ik.start());
  measured.write(q);
  clock.advance(1ms);
  KDL::Frame pose = ik.call<KDL::Frame>("forward", q);
  pose.p += KDL::Vector(0.0, 0.0, 1e-4);
  desired.write(pose);
  clock.advance(1ms);
  KDL::JntArray solved;
  ASSERT_EQ(command.read(solved), core::FlowStatus::NewData) << ik.call<std::string>("lastIkStatus");
  EXPECT_TRUE(KDL::Equal(ik.call<KDL::Frame>("forward", solved), pose, 1e-9));
  ASSERT_TRUE(ik.stop());
  ASSERT_TRUE(ik.cleanup());

  ik.setProperty("solver", std::string("kdl_lma"));
  const core::Result refused = ik.configure();
  ASSERT_FALSE(refused);
  EXPECT_CONTAINS(refused.message, "component 'IK': property solver is 'kdl_lma': KDL's Levenberg-Marquardt solver");
  EXPECT_CONTAINS(refused.message, "libompl");
  EXPECT_CONTAINS(refused.message, "set solver to kdl_nr or closed_form");
}

}  // namespace
}  // namespace cobra::components
