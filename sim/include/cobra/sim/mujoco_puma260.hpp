#pragma once
/// @file
/// The Puma 260 world in MuJoCo (2.2): the arm, the FTSens at the flange, the contact tool and the
/// curved surface of thesis §6.4, loaded from an MJCF file (apps/puma260/world/puma260.xml is the
/// reference model; its comments give every number). MujocoPuma260World is the physics (MuJoCo
/// integrates; torques in, joint state, sensor wrench and contact out); MujocoPuma260Arm puts the
/// six CiA 402 drives in front of it as a sim::Puma260Plant for the simulated EtherCAT bus.
/// SI units throughout (m, rad, s, N, N·m); poses in the base (MuJoCo world) frame.

#include <array>
#include <memory>
#include <string>

#include <kdl/frames.hpp>

#include "cobra/sim/puma260_arm.hpp"
#include "cobra/sim/puma260_plant.hpp"

struct mjModel_;
struct mjData_;

namespace cobra::sim {

/// The unexpected surface: a cylinder (the model's geom `surface`), in the base frame.
struct CylinderSurface {
  KDL::Vector centre;      ///< m
  KDL::Vector axis;        ///< unit vector
  double radius = 0.0;       ///< m
  double half_length = 0.0;  ///< m
};

/// Names the world looks up in the MJCF file.
namespace mjcf_names {
inline constexpr const char* kJoints[6] = {"joint1", "joint2", "joint3", "joint4", "joint5", "joint6"};
inline constexpr const char* kSensorSite = "ftsens";    ///< the FTSens sensor frame (on the tool body)
inline constexpr const char* kToolTipSite = "tool_tip"; ///< the tool tip, flange axes
inline constexpr const char* kFlangeSite = "flange";    ///< DH frame 6
inline constexpr const char* kForceSensor = "ftsens_force";
inline constexpr const char* kTorqueSensor = "ftsens_torque";
inline constexpr const char* kToolBall = "tool_ball";   ///< sphere geom at the tool's end
inline constexpr const char* kSurface = "surface";      ///< cylinder geom
}  // namespace mjcf_names

/// A loaded MJCF world of the Puma 260. Everything is allocated by the constructor (MuJoCo's
/// mjData included); the stepping and query functions are noexcept, allocation-free and
/// deterministic. Not thread-safe: one owner steps it.
class MujocoPuma260World {
 public:
  static constexpr int kJoints = 6;

  /// Loads `path` and checks it: 6 hinge joints joint1..joint6, 6 motor actuators (one per
  /// joint, in joint order), the sites ftsens / tool_tip / flange, force and torque sensors at
  /// ftsens, a sphere tool_ball on the tool, a cylinder `surface` within reach of the shoulder.
  /// @throws std::invalid_argument with one line starting "<path>: " saying what is wrong and what
  /// was expected (MuJoCo's own text for a file it cannot read or parse).
  explicit MujocoPuma260World(const std::string& path);
  ~MujocoPuma260World();
  MujocoPuma260World(const MujocoPuma260World&) = delete;
  MujocoPuma260World& operator=(const MujocoPuma260World&) = delete;

  const std::string& path() const noexcept { return path_; }
  /// The model's integration step (s).
  double timestep() const noexcept { return timestep_; }
  /// Simulated time since load (s).
  double time() const noexcept;

  /// Puts the arm at `q` (rad) at rest and recomputes everything (kinematics, contacts, sensors).
  void setJointPositions(const std::array<double, 6>& q) noexcept;
  /// Motor torques (N·m; MuJoCo clamps them to the actuators' ctrlrange) held until changed.
  void setMotorTorque(int joint, double newton_metre) noexcept;
  /// Engages (true) or releases the holding brake of `joint`, which stops and holds the joint
  /// with at most `torque` N·m (>= 0).
  void setBrake(int joint, bool engaged, double torque) noexcept;
  /// One integration step of `h` s (> 0): MuJoCo's mj_step with timestep h. An engaged brake
  /// applies, clamped to its torque, the joint torque that brings the joint to rest by the end of
  /// the step (gravity, Coriolis and passive forces of this step compensated, the velocity
  /// removed through the joint's row of the mass matrix): a fail-safe brake that does not slip
  /// below its rating.
  void integrate(double h) noexcept;
  /// Advances by `dt` s in steps of at most timestep() with the torques held (no drives).
  void step(double dt) noexcept;

  double jointPosition(int joint) const noexcept;  ///< rad
  double jointVelocity(int joint) const noexcept;  ///< rad/s
  /// Gravity + Coriolis torques MuJoCo computed at the last step (qfrc_bias, N·m).
  double biasTorque(int joint) const noexcept;

  /// The wrench the tool exerts on the FTSens (N, N·m), about the sensor frame's origin and in
  /// its axes: at rest, the contact force on the tool plus the tool's weight (MuJoCo's
  /// force/torque sensors give the opposite, the sensor's wrench on the tool).
  KDL::Wrench sensorWrench() const noexcept;
  KDL::Frame sensorPose() const noexcept;  ///< the FTSens sensor frame in the base frame (m)
  KDL::Frame flangePose() const noexcept;  ///< DH frame 6 in the base frame (m)
  KDL::Frame toolPose() const noexcept;    ///< the tool tip in the base frame (m), flange axes
  /// Sensor frame to tool tip (from the model; 0.10 m along z in the reference model).
  KDL::Frame sensorToTool() const noexcept { return sensor_to_tool_; }
  /// Flange to sensor frame (0.018 m along z in the reference model).
  KDL::Frame flangeToSensor() const noexcept { return flange_to_sensor_; }

  /// Sum of the normal forces between the tool's geoms and the surface (N, >= 0).
  double contactForce() const noexcept;
  /// Depth of the tool's ball inside the surface cylinder (m, >= 0; 0 off contact): radius of the
  /// ball plus radius of the cylinder minus the distance of the ball's centre from the axis, while
  /// the centre is within the cylinder's length.
  double penetration() const noexcept;
  const CylinderSurface& surface() const noexcept { return surface_; }
  double toolBallRadius() const noexcept { return ball_radius_; }
  /// Mass of the tool body (kg): what the sensor carries beyond its frame.
  double toolMass() const noexcept { return tool_mass_; }

  /// How many warnings MuJoCo raised since load (mjData.warning: bad accelerations, after which
  /// MuJoCo resets the state, full contact or constraint buffers, ...): 0 in a sound run.
  int warningCount() const noexcept;

  /// MuJoCo's model and data, for tests and tools (not part of the control interface).
  mjModel_* model() noexcept { return model_; }
  mjData_* data() noexcept { return data_; }

 private:
  KDL::Frame sitePose(int site) const noexcept;

  std::string path_;
  mjModel_* model_ = nullptr;
  mjData_* data_ = nullptr;
  double timestep_ = 0.0;
  std::array<int, 6> qpos_{}, dof_{}, actuator_{};
  std::array<double, 6> brake_{};  // N·m, 0: released
  std::unique_ptr<double[]> momentum_;  // M·qvel, nv (allocated at load)
  int sensor_site_ = -1, tool_site_ = -1, flange_site_ = -1;
  int force_adr_ = -1, torque_adr_ = -1;
  int ball_geom_ = -1, surface_geom_ = -1, tool_body_ = -1;
  CylinderSurface surface_;
  double ball_radius_ = 0.0, tool_mass_ = 0.0;
  KDL::Frame sensor_to_tool_, flange_to_sensor_;
};

/// The six CiA 402 drives on the MuJoCo arm: each integration step of the world, every drive's
/// loops compute a torque from the measured joint state and MuJoCo integrates the arm under it
/// (the drives' own motor models are not used). A joint whose drive is unpowered is held by its
/// brake (`Puma260ArmModel::brake_torque`). The drives' velocity loops are tuned for the inertia
/// the joint sees at the initial position (the drive model's `inertia` is replaced by MuJoCo's
/// joint-space mass matrix diagonal there, armature included), as a drive's auto-tuning would.
class MujocoPuma260Arm final : public Puma260Plant {
 public:
  /// Puma260ArmModel::defaults() with the loops tuned for contact: velocity loop 10 Hz, position
  /// gain 30 1/s (ASSUMPTION). With the analytic arm's 40 Hz and 60 1/s, the six loops and the
  /// surface's contact (about 4e4 N/m) fall into a limit cycle when the tool is pressed on the
  /// surface (forces jumping between 0 and 50 N, then an over-current fault); with these they hold
  /// a press of 0.2-0.8 mm at a steady 9-35 N (measured: sim/test/mujoco_puma260_test.cpp).
  static Puma260ArmModel defaultDrives();

  /// @param initial joint positions (rad) at power-on
  /// @throws std::invalid_argument for a bad file (see MujocoPuma260World) or drive model.
  MujocoPuma260Arm(const std::string& path, const Puma260ArmModel& drives, const std::array<double, 6>& initial);

  Cia402Drive& drive(int joint) noexcept override { return drives_[static_cast<std::size_t>(joint)]; }
  const Cia402Drive& drive(int joint) const noexcept override { return drives_[static_cast<std::size_t>(joint)]; }
  /// Advances by `dt` s in ceil(dt / timestep) equal integration steps.
  void step(double dt) noexcept override;

  MujocoPuma260World& world() noexcept { return *world_; }
  const MujocoPuma260World& world() const noexcept { return *world_; }

 private:
  std::unique_ptr<MujocoPuma260World> world_;
  Puma260ArmModel model_;
  std::array<Cia402Drive, 6> drives_;
};

}  // namespace cobra::sim
