#pragma once
/// @file
/// The simulated retrofitted Puma 260 (thesis §6.1.1): six Elmo drives on the analytic arm, on a
/// simulated EtherCAT bus: the sim-world side of Puma260EtherCATMaster's `bus = "sim:<this
/// component's name>"`. Puma260World is the MuJoCo world (FTSens, tool, surface) behind the same bus.

#include <kdl/jntarray.hpp>
#include <string>

#include "cobra/components/sim/simulated_puma260_base.hpp"

namespace cobra::components {

/// Bridge (the simulated world). Needs a periodic activity: each update applies the newest
/// process data the master sent in earlier steps, steps the arm (sim::Puma260Arm: drives, gravity,
/// brakes; no contact) by the time since the previous update and publishes the drives' inputs,
/// which the master sees from its next step on (sim/device_link.hpp), whatever the order of the
/// two in the deployment. At configure the bus is registered as `sim:<name>`
/// (core::BackendRegistry<fieldbus::Cia402Bus>); configure it before its master.
///
/// Properties: `initial_position` (6 joint angles at power-on, rad; default: the Puma's nominal
/// pose qn, where Puma260EtherCATMaster's default nest is).
///
/// Ports: out `trueJointPosition` (rad: the joints as they are, ground truth for the world).
///
/// Operations (fault injection): `injectFault(i)` (over-current fault in drive i, 0-5),
/// `injectWorkingCounterFault(n)` (the next n bus cycles come back with a wrong working counter).
class SimulatedPuma260 : public SimulatedPuma260Base {
 public:
  explicit SimulatedPuma260(std::string name);

 protected:
  bool configureHook() override;
  void updateHook() override;

 private:
  core::OutputPort<KDL::JntArray> true_position_{"trueJointPosition", "joint angles of the simulated arm", "rad"};
  KDL::JntArray out_{6};
};

}  // namespace cobra::components
