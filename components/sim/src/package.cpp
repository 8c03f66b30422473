#include "cobra/components/sim/package.hpp"

#include "cobra/components/sim/cryo_console.hpp"
#include "cobra/components/sim/patient_simulator.hpp"
#include "cobra/components/sim/puma260_world.hpp"
#include "cobra/components/sim/simulated_ftsens.hpp"
#include "cobra/components/sim/simulated_leap_motion.hpp"
#include "cobra/components/sim/simulated_omni_phantom.hpp"
#include "cobra/components/sim/simulated_puma260.hpp"
#include "cobra/components/sim/simulated_robot.hpp"
#include "cobra/components/sim/wound_simulator.hpp"

namespace cobra::components {

void registerSimPackage(deploy::PackageBuilder& package) {
  package
      .component<SimulatedISURRobot>(
          "SimulatedISURRobot", "simulated I-SUR puncturing robot with the ISURRobotBridge interface (thesis §4.5.7)")
      .component<SimulatedISURSuturingRobot>(
          "SimulatedISURSuturingRobot",
          "simulated two-armed I-SUR suturing robot (thesis §5.3): Endo Stitch and gripper arms, split IK, Endo Stitch "
          "actuation")
      .component<SimulatedUR5Robot>("SimulatedUR5Robot",
                                    "simulated UR5 with the UR5RobotBridge interface (thesis §4.5.8)")
      .component<PatientSimulator>(
          "PatientSimulator", "abdomen phantom, needle-tissue forces, cryo iceball and ultrasound image (thesis §4.2)")
      .component<SimulatedOmniPhantom>("SimulatedOmniPhantom",
                                       "simulated Phantom Omni with the OmniPhantomBridge interface (thesis §4.5.9)")
      .component<SimulatedPuma260>("SimulatedPuma260",
                                   "simulated Puma 260 drives on EtherCAT, for Puma260EtherCATMaster bus = sim:<name>")
      .component<Puma260World>("Puma260World",
                               "the Puma 260 world in MuJoCo (arm, drives, FTSens, tool, curved surface), for "
                               "Puma260EtherCATMaster bus = sim:<name>")
      .component<SimulatedFTSens>("SimulatedFTSens", "simulated IIT FTSens on CAN, for FTSensDriver bus = sim:<name>")
      .component<SimulatedLeapMotion>("SimulatedLeapMotion",
                                      "simulated Leap Motion, for LeapMotionDriver device = sim:<name>")
      .component<CryoConsole>("CryoConsole",
                              "simulated cryoablation console: freezes and thaws the patient on request (thesis ch. 4)")
      .component<WoundSimulator>("WoundSimulator",
                                 "simulated suturing patient: wound, stitches, thread and its edges (thesis ch. 5)");
}

}  // namespace cobra::components
