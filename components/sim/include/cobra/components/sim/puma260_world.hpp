#pragma once
/// @file
/// The Puma 260 world of thesis §6.4 in MuJoCo: the arm behind its six simulated Elmo drives on a
/// simulated EtherCAT bus, the FTSens at the flange, the contact tool and the unexpected curved
/// surface. The sim-world side of Puma260EtherCATMaster's `bus = "sim:<this component's name>"`;
/// its `sensorWrench` feeds SimulatedFTSens.trueWrench (FTSens -> CAN -> FTSensDriver).

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <string>
#include <vector>

#include "cobra/components/sim/simulated_puma260_base.hpp"
#include "cobra/sim/mujoco_puma260.hpp"

namespace cobra::components {

/// Bridge (the simulated world; package cobra_sim). Needs a periodic activity: each update applies
/// the newest process data the master sent, steps the MuJoCo world (sim::MujocoPuma260Arm: the
/// drives' loops compute torque, MuJoCo integrates in steps of the model's timestep) by the time
/// since the previous update and publishes the drives' inputs and the world's truth. At configure
/// the bus is registered as `sim:<name>` (core::BackendRegistry<fieldbus::Cia402Bus>); configure
/// it before its master. Nothing else integrates the arm.
///
/// Properties: `model` (path of the MJCF file, e.g. apps/puma260/world/puma260.xml; relative to
/// the working directory: a deployment file builds it from its own folder), `initial_position`
/// (6 joint angles at power-on, rad; default: Puma260EtherCATMaster's default nest, the encoder
/// initialisation position), `seed` (of the encoder noise), `encoder_noise` (rad, >= 0: standard
/// deviation of the Gaussian noise on the joint positions the drives report; default 0).
///
/// Ports (out): `sensorWrench` (KDL::Wrench, N and N·m: the wrench the tool exerts on the FTSens,
/// about the sensor frame's origin, in its axes; 0.018 m beyond the flange in the reference model),
/// `toolPose` (KDL::Frame, m: the true tool tip in the base frame, flange axes), `contactForce`
/// (double, N: normal force between the tool and the surface, 0 off contact), `penetration`
/// (double, m, >= 0: depth of the tool's ball in the surface), `truePosition` (KDL::JntArray, rad:
/// the joints as they are).
///
/// Read-only property `surface_cylinder` (vector<double>, m, set at configure from the MJCF file):
/// the curved surface's cylinder as its axis' end points a (x y z) and b (x y z) and its radius,
/// in the base frame (what cobra studio draws).
///
/// Operations: `injectFault(i)` (over-current fault in drive i, 0-5), `injectWorkingCounterFault(n)`
/// (the next n bus cycles come back with a wrong working counter: the last slave does not process
/// its datagram), `surface()` (a line describing the surface cylinder in the base frame).
class Puma260World : public SimulatedPuma260Base {
 public:
  explicit Puma260World(std::string name);

 protected:
  bool configureHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  std::string describeSurface() const;

  core::Property<std::string> model_{"model", "", "path", "MJCF file of the world (apps/puma260/world/puma260.xml)"};
  core::Property<int> seed_{"seed", 1, "", "seed of the encoder noise"};
  core::Property<double> encoder_noise_{"encoder_noise", 0.0, "rad",
                                        "standard deviation of the noise on the reported joint positions"};
  core::Property<std::vector<double>> surface_cylinder_{
      "surface_cylinder", {}, "m", "set at configure: the surface cylinder's axis end points (x y z each) and radius, base frame"};
  core::OutputPort<KDL::Wrench> sensor_wrench_{"sensorWrench",
                                               "wrench the tool exerts on the FTSens, sensor frame", "N, N·m"};
  core::OutputPort<KDL::Frame> tool_pose_{"toolPose", "true tool tip pose in the base frame", "m"};
  core::OutputPort<double> contact_force_{"contactForce", "normal force tool-surface, 0 off contact", "N"};
  core::OutputPort<double> penetration_{"penetration", "depth of the tool's ball in the surface, >= 0", "m"};
  core::OutputPort<KDL::JntArray> true_position_{"truePosition", "joint angles of the simulated arm", "rad"};

  sim::MujocoPuma260Arm* arm_ = nullptr;  // owned by the bus
  KDL::JntArray out_{6};
};

}  // namespace cobra::components
