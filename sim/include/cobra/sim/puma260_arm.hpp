#pragma once
/// @file
/// The retrofitted Puma 260 behind its six Elmo drives (thesis §6.1.1): six CiA 402 drives
/// (Cia402Drive) turning the joints, with gravity acting on the shoulder and elbow. Joint-side SI
/// units (rad, rad/s, N·m). A bus adapter (cobra::fieldbus) puts it behind a cyclic process-data
/// interface.

#include <array>

#include "cobra/sim/cia402_drive.hpp"
#include "cobra/sim/puma260_plant.hpp"

namespace cobra::sim {

/// Arm description. Link masses and centres of mass are ASSUMPTIONS of the order of a Puma 260
/// (total arm mass about 13 kg; the thesis gives none); lengths follow kinematics/puma260.hpp
/// (a2 = 0.2032 m upper arm). In that DH convention the height of the upper arm's centre of mass
/// is d1 + r2·sin(q2) and the forearm's d1 + a2·sin(q2) + r3·cos(q2 + q3), so the gravity torques
/// the shoulder and elbow drives must hold are
///   τ2 = g·(m2·r2·cos q2 + m3·(a2·cos q2 − r3·sin(q2 + q3))),  τ3 = −g·m3·r3·sin(q2 + q3).
struct Puma260ArmModel {
  std::array<Cia402DriveModel, 6> drives{};  ///< one per joint, joint side (see Cia402DriveModel)
  double upper_arm_mass = 2.0;               ///< kg, >= 0: m2 (ASSUMPTION)
  double upper_arm_com = 0.10;               ///< m, >= 0: r2, shoulder axis to the upper arm's centre of mass
  double forearm_mass = 1.5;                 ///< kg, >= 0: m3, forearm + wrist + tool (ASSUMPTION)
  double forearm_com = 0.12;                 ///< m, >= 0: r3, elbow axis to the forearm's centre of mass
  double upper_arm_length = 0.2032;          ///< m, > 0: a2 (kinematics::Puma260Parameters)
  double gravity = 9.81;                     ///< m/s², >= 0
  double brake_torque = 20.0;                ///< N·m, >= 0: holding brakes of unpowered joints (ASSUMPTION)

  /// Default drives with the joint inertias scaled to the links they move (ASSUMPTION:
  /// 0.05/0.08/0.03 kg·m² for joints 1-3, 0.005 for the wrist).
  static Puma260ArmModel defaults();
};

/// @throws std::invalid_argument naming the parameter (and the joint) and the expected range.
void validate(const Puma260ArmModel& model);

/// Six drives plus gravity. `step(dt)` sets each drive's load torque from the current joint
/// positions, then steps every drive by dt (s). A joint whose drive is not powered (neither
/// Operation enabled nor Quick stop active) is held by its brake: gravity does not move it and
/// a moving joint is stopped with at most `brake_torque` (ASSUMPTION: fail-safe brakes that
/// engage with the power stage off). noexcept, no
/// allocation, deterministic.
class Puma260Arm final : public Puma260Plant {
 public:

  /// @param initial joint positions (rad)
  /// @throws std::invalid_argument when the model is invalid or a position is not finite.
  explicit Puma260Arm(const Puma260ArmModel& model, const std::array<double, 6>& initial = {});

  Cia402Drive& drive(int joint) noexcept override { return drives_[static_cast<std::size_t>(joint)]; }
  const Cia402Drive& drive(int joint) const noexcept override { return drives_[static_cast<std::size_t>(joint)]; }
  void step(double dt) noexcept override;

  /// Gravity torque (N·m) each joint must hold at joint positions `q` (rad).
  std::array<double, 6> gravityTorque(const std::array<double, 6>& q) const noexcept;
  const Puma260ArmModel& model() const noexcept { return model_; }

 private:
  Puma260ArmModel model_;
  std::array<Cia402Drive, 6> drives_;
};

}  // namespace cobra::sim
