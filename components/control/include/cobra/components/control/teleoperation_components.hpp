#pragma once
/// @file
/// The Transparency and Passivity layers of the thesis' teleoperation (§4.5.4, Fig. 4.15) as
/// components: thin adapters around cobra::control's layers, on SE(3): poses (m), twists (m/s,
/// rad/s) and wrenches (N, N·m) whole, all in the base frame.

#include <kdl/frames.hpp>
#include <optional>

#include "cobra/control/teleoperation.hpp"
#include "cobra/core/component.hpp"

namespace cobra::components {

/// Calculation. In: `masterPose`, `masterTwist`, `slavePose`, `slaveTwist`. Out:
/// `masterForceDesired`, `slaveForceDesired` (F_md, F_sd of eq. 4.15, wrenches). Operation
/// `engage()` switches to teleoperation now (rest lengths = the current translation and rotation
/// offsets): until then both are zero. Properties: `stiffness` (K, N/m), `damping` (B, N·s/m),
/// `rotational_stiffness` (K_r, N·m/rad; 0, the default: rotation uncoupled, for a master that
/// measures no orientation such as the simulated Omni), `rotational_damping` (B_r, N·m·s/rad),
/// `compensation_time` (t_c, s), `error_low`/`error_high` (ē1, ē2, m), `rest_low`/`rest_high`
/// (λ̄1, λ̄2, m), `rotation_error_low`/`rotation_error_high` and
/// `rotation_rest_low`/`rotation_rest_high` (the same for the rotation angle, rad).
class TransparencyLayerComponent : public core::Component {
 public:
  explicit TransparencyLayerComponent(std::string name);

 protected:
  bool configureHook() override;
  void updateHook() override;

 private:
  void engage();
  double seconds() const;

  core::Property<double> stiffness_{"stiffness", 50.0, "N/m", "K of the master-slave coupling"};
  core::Property<double> damping_{"damping", 1.1, "N·s/m", "B of the master-slave coupling"};
  core::Property<double> rotational_stiffness_{"rotational_stiffness", 0.0, "N·m/rad",
                                              "K_r of the rotation coupling (0: rotation not coupled)"};
  core::Property<double> rotational_damping_{"rotational_damping", 0.0, "N·m·s/rad", "B_r of the rotation coupling"};
  core::Property<double> compensation_time_{"compensation_time", 2.0, "s", "t_c: the offset is gone after it"};
  core::Property<double> error_low_{"error_low", 0.005, "m", "ē1: below it the slave feels the whole coupling"};
  core::Property<double> error_high_{"error_high", 0.010, "m", "ē2: above it the slave feels none"};
  core::Property<double> rest_low_{"rest_low", 0.005, "m", "λ̄1"};
  core::Property<double> rest_high_{"rest_high", 0.010, "m", "λ̄2"};
  core::Property<double> rotation_error_low_{"rotation_error_low", 0.05, "rad", "ē1 of the rotation error angle"};
  core::Property<double> rotation_error_high_{"rotation_error_high", 0.10, "rad", "ē2 of the rotation error angle"};
  core::Property<double> rotation_rest_low_{"rotation_rest_low", 0.05, "rad", "λ̄1 of the rest rotation angle"};
  core::Property<double> rotation_rest_high_{"rotation_rest_high", 0.10, "rad", "λ̄2 of the rest rotation angle"};
  core::InputPort<KDL::Frame> master_pose_{"masterPose", "master pose", "m"};
  core::InputPort<KDL::Twist> master_twist_{"masterTwist", "master twist, base frame", "m/s, rad/s"};
  core::InputPort<KDL::Frame> slave_pose_{"slavePose", "slave pose", "m"};
  core::InputPort<KDL::Twist> slave_twist_{"slaveTwist", "slave twist, base frame", "m/s, rad/s"};
  core::OutputPort<KDL::Wrench> master_force_{"masterForceDesired", "F_md, base frame", "N, N·m"};
  core::OutputPort<KDL::Wrench> slave_force_{"slaveForceDesired", "F_sd, base frame", "N, N·m"};
  std::optional<control::TransparencyLayer> layer_;
  KDL::Frame master_, slave_;
  KDL::Twist master_velocity_, slave_velocity_;
};

/// Calculation. In: `masterForceDesired`, `slaveForceDesired` (wrenches), `masterTwist`,
/// `slaveTwist`, `masterDissipation`, `slaveDissipation` (W; 0 until written: wire the master's
/// and the slave's `dissipatedPower`). Out: `masterForce`, `slaveForce` (implemented wrenches: a
/// tank pays force·v + torque·ω), `masterTankEnergy`, `slaveTankEnergy` (J). Properties per tank
/// (`master_`/`slave_` + `minimum`, `request`, `available`, `maximum`, `initial`, J) and
/// `transfer_power` (P̄, W). Needs a periodic activity. Events: e_master_limited /
/// e_slave_limited when a tank first refuses a force.
class PassivityLayerComponent : public core::Component {
 public:
  explicit PassivityLayerComponent(std::string name);

 protected:
  bool configureHook() override;
  void updateHook() override;

 private:
  core::Property<double> master_levels_[5];
  core::Property<double> slave_levels_[5];
  core::Property<double> transfer_power_{"transfer_power", 1.0, "W", "P̄: rate of the exchange between tanks"};
  core::Property<double> master_max_force_{"master_max_force", -1.0, "N",
                                           "the force the master device renders (its saturation): the master "
                                           "tank pays for the force cut to it; < 0: any force"};
  core::Property<double> master_max_torque_{"master_max_torque", -1.0, "N·m",
                                            "the torque the master device renders (0: a device without "
                                            "actuated wrist); < 0: any torque"};
  core::InputPort<KDL::Wrench> master_desired_{"masterForceDesired", "F_md, base frame", "N, N·m"};
  core::InputPort<KDL::Wrench> slave_desired_{"slaveForceDesired", "F_sd, base frame", "N, N·m"};
  core::InputPort<KDL::Twist> master_twist_{"masterTwist", "master twist, base frame", "m/s, rad/s"};
  core::InputPort<KDL::Twist> slave_twist_{"slaveTwist", "slave twist, base frame", "m/s, rad/s"};
  core::InputPort<double> master_dissipation_{"masterDissipation", "power the master's damping dissipates", "W"};
  core::InputPort<double> slave_dissipation_{"slaveDissipation", "power the slave's damping dissipates", "W"};
  core::OutputPort<KDL::Wrench> master_force_{"masterForce", "implemented wrench on the master", "N, N·m"};
  core::OutputPort<KDL::Wrench> slave_force_{"slaveForce", "implemented wrench on the slave", "N, N·m"};
  core::OutputPort<double> master_energy_{"masterTankEnergy", "master tank", "J"};
  core::OutputPort<double> slave_energy_{"slaveTankEnergy", "slave tank", "J"};
  std::optional<control::PassivityLayer> layer_;
  KDL::Wrench master_wanted_, slave_wanted_;
  KDL::Twist master_velocity_, slave_velocity_;
  double master_power_ = 0.0, slave_power_ = 0.0;
  bool master_limited_ = false, slave_limited_ = false;
};

}  // namespace cobra::components
