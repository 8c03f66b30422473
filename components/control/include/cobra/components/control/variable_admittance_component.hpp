#pragma once
/// @file
/// The thesis' Variable Admittance Controller component (§4.5.3): a thin adapter around
/// cobra::control::VariableAdmittance.

#include <kdl/frames.hpp>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>
#include <memory>
#include <vector>

#include "cobra/control/variable_admittance.hpp"
#include "cobra/core/component.hpp"

namespace cobra::components {

/// Calculation component. Properties (each matrix as 6 numbers, its diagonal, or 36 numbers,
/// row-major; [translation; rotation]): `inertia` (kg, kg·m²), `damping` (N·s/m, N·m·s/rad),
/// `stiffness` (N/m, N·m/rad) — changed at run time by configurations, without a jump in the
/// commanded pose —, `constant_inertia` and `constant_stiffness` (the smallest values ever
/// implemented, fixed at configure), and the tank's `tank_initial`, `tank_max`, `tank_min` (J).
/// Ports: `refPose`, `refTwist` (the trajectory's set-point), `measWrench` (base frame, N, N·m)
/// and `extWrench` (added to it while connected: a teleoperation coupling force) in; `admPose`, `admTwist`, `tankEnergy` (J) out;
/// `dissipatedPower` (W) out: the power the step dissipated that the admittance's own tank did not
/// store (all of it while that tank is full, else 0; 0 while held or blind): the slave's D_s for the
/// teleoperation's PassivityLayer.slaveDissipation, so no dissipated energy fills two tanks. Needs a periodic activity: dt is its period.
/// Events: e_tank_empty when the variable parts stop being implemented, e_tank_refilled when they
/// are again, e_bad_parameters when a configuration's matrices are refused (the old ones stay),
/// e_reference_jump when refPose moved between two steps faster than `max_reference_speed` (m/s)
/// or turned faster than `max_reference_angular_speed` (rad/s): a new trajectory starting
/// elsewhere (at the measured pose, after a teleoperation, ...). The controller then rebases
/// (control::VariableAdmittance::rebase): admPose stays continuous and converges to the new
/// reference through the admittance's dynamics.
/// Re-sync (ARCHITECTURE §7, "Continuity in the control path"): `heldPose` (in, base frame, m)
/// is written by whatever holds the robot this controller commands — the robot bridge refusing a
/// command (e_ik_discontinuity), a kinematics solver, a state validator, a drive's quick stop —
/// with the pose the robot holds, in each step it holds. On such a sample the controller restarts
/// its output there (control::VariableAdmittance::resync: at rest, in equilibrium with the
/// measured wrench): admPose is the held pose in that very step, admTwist zero, and e_resynced
/// is emitted (once while held step after step).
/// It then steps about the reference that puts its output at the held pose, ignoring refPose's
/// old sample (and refTwist) until refPose brings a new one: a trajectory generator that
/// stopped, or a teleoperation reference moving on (a jump to rebase on, as above). So the
/// command never runs away from a held robot, and the next command starts where the robot is.
/// `heldRefPose` (out, base frame, m) carries that reference in each re-sync step: connected to
/// the held-pose input of whatever produces refPose (CartesianTrajectoryGenerator's heldPose_i),
/// the producer re-syncs to it, and its next set-point is exactly the reference the controller
/// steps about (in contact, the held pose less the compliance displacement): no jump, no drift.
/// A held pose before this controller has commanded anything is ignored.
/// Blind: with `wrench_timeout` > 0 (s), when measWrench has brought no new sample for longer than
/// that (a silent force sensor), the admittance HOLDS: admPose stays where it was, admTwist is
/// zero, the controller is not stepped (it would push on with a stale force), and e_wrench_lost is
/// emitted once; the next sample resumes it from the held state (e_wrench_restored). 0 (default):
/// the last sample is used however old it is.
/// Non-finite input: a measWrench or extWrench sample with a NaN or infinite component (a broken
/// sensor chain) is refused: the controller is not stepped and not re-synced (either would carry
/// the value into its state), admPose keeps its last sample (the robot holds), admTwist is zero,
/// and e_input_not_finite is emitted once per episode (again after a finite sample of both). The
/// operation `lastFailure` (for `cobra run`'s safe stop) says when and on which port.
/// Holding on a non-finite input (each step of the episode) and on entering Exception (a hook
/// threw: nothing steps any more), the controller writes `heldRefPose` too, with the reference its
/// last output was stepped about: the producer of refPose (CartesianTrajectoryGenerator's
/// heldPose_i) ends its motion there at once and holds every arm it drives at its current
/// set-point, so the other arms of a coordinated motion stop with this one instead of running
/// on through a stop motion (one arm frozen, the other decelerating along the pair's path).
/// Nothing is written before the controller has commanded anything.
class VariableAdmittanceController : public core::Component {
 public:
  explicit VariableAdmittanceController(std::string name);
  ~VariableAdmittanceController() override;
  /// The controller (nullptr before configure): for tests and plots.
  const control::VariableAdmittance* controller() const { return controller_.get(); }
  /// "at 31.816 s Admittance refused a non-finite measWrench sample; it holds its last admPose"
  /// (the last refusal), or "no non-finite input refused". Any thread.
  std::string lastFailure() const;

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void exceptionHook() override;

 private:
  /// Writes heldRefPose (the reference of the last step) once the controller has stepped.
  void holdProducer() noexcept;
  /// True when the reference moved or turned faster than max_reference_speed /
  /// max_reference_angular_speed over `dt` s since the last step (a jump to rebase on).
  bool referenceJumped(double dt) const noexcept;

  core::Property<std::vector<double>> inertia_{"inertia", {2, 2, 2, 0.1, 0.1, 0.1}, "kg, kg·m²", "Λd: 6 (diagonal) or 36 numbers"};
  core::Property<std::vector<double>> damping_{"damping", {60, 60, 60, 2, 2, 2}, "N·s/m, N·m·s/rad", "D: 6 or 36 numbers"};
  core::Property<std::vector<double>> stiffness_{"stiffness", {500, 500, 500, 10, 10, 10}, "N/m, N·m/rad", "Kd: 6 or 36 numbers"};
  core::Property<std::vector<double>> constant_inertia_{"constant_inertia", {1, 1, 1, 0.05, 0.05, 0.05}, "kg, kg·m²",
                                                        "Λc: the smallest inertia (fixed at configure)"};
  core::Property<std::vector<double>> constant_stiffness_{"constant_stiffness", {50, 50, 50, 1, 1, 1}, "N/m, N·m/rad",
                                                          "Kc: the smallest stiffness (fixed at configure)"};
  core::Property<double> tank_initial_{"tank_initial", 5.0, "J", "energy in the tank at start"};
  core::Property<double> tank_max_{"tank_max", 20.0, "J", "T̄: the tank stores nothing above it"};
  core::Property<double> tank_min_{"tank_min", 1.0, "J", "ε: the tank never goes below it"};
  core::Property<double> max_reference_speed_{"max_reference_speed", 1.0, "m/s",
                                              "faster reference motion between two steps is a jump, > 0"};
  core::Property<double> max_reference_angular_speed_{"max_reference_angular_speed", 3.0, "rad/s",
                                                      "faster reference rotation between two steps is a jump, > 0"};

  core::Property<double> wrench_timeout_{"wrench_timeout", 0.0, "s",
                                         "hold when measWrench is silent for longer than this, >= 0 (0: never)"};
  core::InputPort<KDL::Frame> ref_pose_{"refPose", "reference pose (base frame)", "m"};
  core::InputPort<KDL::Twist> ref_twist_{"refTwist", "reference twist (base frame)", "m/s, rad/s"};
  core::InputPort<KDL::Wrench> meas_wrench_{"measWrench", "measured external wrench (base frame, at the tool point)", "N, N·m"};
  core::InputPort<KDL::Wrench> ext_wrench_{"extWrench",
                                           "added to measWrench while connected, e.g. a teleoperation coupling force "
                                           "(base frame, at the tool point)",
                                           "N, N·m"};
  core::InputPort<KDL::Frame> held_pose_{"heldPose",
                                         "the pose the commanded robot holds (base frame), from whatever holds it: a "
                                         "sample re-syncs the output to it",
                                         "m"};
  core::OutputPort<KDL::Frame> held_ref_pose_{
      "heldRefPose",
      "written at each re-sync, and while holding on a non-finite input or in Exception: the reference whose output "
      "is the held pose (base frame); the held pose for whatever produces refPose",
      "m"};
  core::OutputPort<KDL::Frame> adm_pose_{"admPose", "the admittance's pose", "m"};
  core::OutputPort<KDL::Twist> adm_twist_{"admTwist", "the admittance's twist", "m/s, rad/s"};
  core::OutputPort<double> tank_energy_{"tankEnergy", "energy in the tank", "J"};
  core::OutputPort<double> dissipated_power_{"dissipatedPower", "dissipated power its own tank did not store", "W"};

  std::unique_ptr<control::VariableAdmittance> controller_;
  std::vector<double> applied_inertia_, applied_damping_, applied_stiffness_;  // what the controller has
  KDL::Frame reference_ = KDL::Frame::Identity();
  KDL::Twist reference_twist_ = KDL::Twist::Zero();
  KDL::Wrench wrench_ = KDL::Wrench::Zero();
  KDL::Wrench ext_wrench_value_ = KDL::Wrench::Zero();
  bool have_reference_ = false;
  KDL::Frame previous_reference_ = KDL::Frame::Identity();  // the reference of the last step
  bool stepped_ = false;                                     // previous_reference_ is set
  bool tank_empty_ = false;
  bool following_held_ = false;  // re-synced: stepping about the held pose until refPose brings a new sample
  bool resynced_ = false;        // the last step re-synced (e_resynced is told once while held step after step)
  std::chrono::nanoseconds last_wrench_{0};  // when measWrench last brought a sample
  bool blind_ = false;                       // holding: measWrench silent for wrench_timeout
  bool not_finite_ = false;                  // holding: a wrench input is not finite (told once)
  // The last refusal, for lastFailure() from any thread: the port's name (a string literal) and
  // when (ns on this component's clock).
  std::atomic<const char*> refused_port_{nullptr};
  std::atomic<std::int64_t> refused_at_{0};
};

/// A 6×6 matrix from 6 numbers (its diagonal) or 36 (row-major); false for any other count.
bool matrixFromProperty(const std::vector<double>& values, control::Matrix6& out) noexcept;

}  // namespace cobra::components
