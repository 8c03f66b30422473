#include "cobra/components/sim/package.hpp"

#include "cobra/components/sim/needle_insertion_monitor.hpp"
#include "cobra/components/sim/patient_simulator.hpp"
#include "cobra/components/sim/simulated_omni_phantom.hpp"
#include "cobra/components/sim/simulated_robot.hpp"
#include "cobra/components/sim/ultrasound_monitor.hpp"

namespace cobra::components {

void registerSimPackage(deploy::PackageBuilder& package) {
  package
      .component<SimulatedISURRobot>(
          "SimulatedISURRobot", "simulated I-SUR puncturing robot with the ISURRobotBridge interface (thesis §4.5.7)")
      .component<SimulatedUR5Robot>("SimulatedUR5Robot",
                                    "simulated UR5 with the UR5RobotBridge interface (thesis §4.5.8)")
      .component<PatientSimulator>(
          "PatientSimulator", "abdomen phantom, needle-tissue forces, cryo iceball and ultrasound image (thesis §4.2)")
      .component<SimulatedOmniPhantom>("SimulatedOmniPhantom",
                                       "simulated Phantom Omni with the OmniPhantomBridge interface (thesis §4.5.9)")
      .component<NeedleInsertionMonitor>("NeedleInsertionMonitor",
                                         "needle insertion events from the measured wrench and pose")
      .component<UltrasoundMonitor>("UltrasoundMonitor", "ultrasound visibility and probe contact events");
}

}  // namespace cobra::components
