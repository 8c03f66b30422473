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

/// Calculation: one side's Passivity layer (Franken et al. 2011), next to its robot: on the
/// master's side beside the haptic device, on the slave's beside the tool's admittance; the two
/// exchange energy only by packets across the link (LinkImpairment's energy ports).
/// In: `forceDesired` (wrench, N, N·m: the Transparency layer's for this robot; on the master's
/// side as it arrives over the link), `twist` (the robot's own, undelayed, m/s, rad/s: what the
/// wrench acts on; zero until written, so a side that renders a force needs it wired),
/// `dissipation` (W: what the robot's damping dissipated; 0 until written), `energyIn` (J: a
/// packet's energy from the other side, taken once per sample written), `peerRequest` (bool: the
/// other side's tank asks, as its last packet said). Out: `force` (the implemented wrench: the
/// tank pays force·v + torque·ω), `energyOut` (J: this period's packet to the other side, written
/// every period, 0 when nothing is sent; energy lost on the way is gone, never made up),
/// `request` (bool: this tank is below T_req), `tankEnergy` (J).
/// Properties: `minimum`, `request`, `available`, `maximum`, `initial` (ε < T_req < T_ava < T̄,
/// T(0), J), `transfer_power` (P̄, W: the most sent per second), `max_force` (N) and `max_torque`
/// (N·m): what the robot renders (< 0: any; 0 and 0: a master that renders nothing, such as a
/// hand tracker: its tank then pays for nothing). Needs a periodic activity. Event:
/// e_force_limited when the tank first refuses a force.
class PassivityLayerComponent : public core::Component {
 public:
  explicit PassivityLayerComponent(std::string name);

 protected:
  bool configureHook() override;
  void updateHook() override;

 private:
  core::Property<double> levels_[5];
  core::Property<double> transfer_power_{"transfer_power", 1.0, "W",
                                         "P̄: the most energy per second this tank sends the other side's"};
  core::Property<double> max_force_{"max_force", -1.0, "N",
                                    "the force the robot renders (its saturation): the tank pays for the force cut "
                                    "to it; < 0: any force"};
  core::Property<double> max_torque_{"max_torque", -1.0, "N·m",
                                     "the torque the robot renders (0: a device without actuated wrist); < 0: any "
                                     "torque"};
  core::InputPort<KDL::Wrench> desired_{"forceDesired", "the Transparency layer's wrench for this robot, base frame",
                                        "N, N·m"};
  core::InputPort<KDL::Twist> twist_{"twist", "this robot's own twist, base frame", "m/s, rad/s"};
  core::InputPort<double> dissipation_{"dissipation", "power this robot's damping dissipates", "W"};
  core::InputPort<double> energy_in_{"energyIn", "energy of a packet from the other side's tank", "J"};
  core::InputPort<bool> peer_request_{"peerRequest", "the other side's tank asks for energy", "1"};
  core::OutputPort<KDL::Wrench> force_{"force", "implemented wrench on this robot, base frame", "N, N·m"};
  core::OutputPort<double> energy_out_{"energyOut", "energy sent to the other side's tank this period", "J"};
  core::OutputPort<bool> request_{"request", "this tank asks for energy (below T_req)", "1"};
  core::OutputPort<double> tank_energy_{"tankEnergy", "this side's tank", "J"};
  std::optional<control::PassivitySide> layer_;
  KDL::Wrench wanted_;
  KDL::Twist velocity_;
  double power_ = 0.0, arrived_ = 0.0;
  bool peer_asks_ = false, limited_ = false;
};

}  // namespace cobra::components
