#pragma once
/// @file
/// Simulated robot bridges (thesis §4.5.7 I-SUR Robot Bridge, §4.5.8 UR5 Robot Bridge) backed by
/// cobra::sim: a stiff position-controlled robot (sim::ServoRobot: first-order lag, joint position
/// and velocity limits, encoder quantisation) commanded in joint or Cartesian space
/// (sim::CartesianServo through the robot's closed-form kinematics), with a simulated
/// force/torque sensor at the tool. Same ports as the network bridges, so a deployment swaps one
/// for the other by changing only the component type.

#include <cstdint>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/kinematics/kinematics_solver.hpp"
#include "cobra/sim/ft_sensor.hpp"
#include "cobra/sim/servo.hpp"

namespace cobra::components {

/// What distinguishes one simulated robot from another: its kinematics and default servo values.
struct SimulatedRobotDefaults {
  std::string robot;                   ///< "I-SUR", "UR5": used in messages
  std::vector<double> initial_joints;  ///< rad / m
  std::vector<double> max_velocity;    ///< rad/s, m/s per joint
  std::vector<double> encoder_counts;  ///< counts per rev (revolute) / per m (prismatic)
  std::string sensor;                  ///< atiNano17, atiNano43 or ftSens
  bool twist_ports = false;            ///< desTwist / measTwist (UR5 §4.5.8)
};

/// Bridge component. Frames: every pose port is the tool pose in the world frame (m, rad):
/// world_T_tool = base_frame · FK(q) · tool_frame, where FK is the robot's kinematics to its own
/// tool point (I-SUR: the needle tip, x = needle axis; UR5: the flange).
///
/// Inputs: `desJointPosition` (KDL::JntArray, rad / m) and `desCartPose` (KDL::Frame, m): the
/// latest new value of either becomes the servo command (both new in one step: the joint command
/// wins; a joint command of the wrong size or with a non-finite value is ignored). A Cartesian
/// command (or a twist step) is turned into joints with the continuity rule of
/// kinematics::ContinuousIk, from the robot's current joint command (its set point): the solution
/// must lie on the IK branch of that command and differ from it by at most max_velocity · dt on
/// every joint (dt: the step length). A command the IK cannot reach (`e_ik_failed`) or that fails
/// the rule (`e_ik_discontinuity`: e.g. a pose across a wrist singularity, a branch flip, a jump)
/// is refused: the last valid command is held and nothing swings. Each event is emitted once per
/// refusal episode; `e_ik_solved` when a Cartesian command is accepted again. `contactWrench`
/// (KDL::Wrench, N, N·m; simulation only): the true wrench the environment applies to the tool,
/// world orientation, reference point at the tool point (PatientSimulator's needleWrench /
/// probeWrench). With `twist_ports`: `desTwist` (KDL::Twist, m/s, rad/s, world orientation,
/// reference point at the tool) integrated onto the commanded pose each step until a newer
/// pose/joint command or for `twist_timeout` s after the last twist received.
///
/// Outputs each update: `measJointPosition` (encoder reading, rad / m), `measCartPose` (FK of the
/// encoder reading, m), `measWrench` (the simulated sensor's reading of contactWrench expressed in
/// the tool frame, reference point at the tool point, N, N·m), `trueCartPose` (simulation only: FK
/// of the true joint position, m: what the physics models must use); with `twist_ports`
/// `measTwist` (m/s, rad/s, world orientation, tool point: the motion of the true pose over the
/// step, as a controller computes it from joint velocities rather than from encoder differences).
///
/// The step length is the time since the previous update on the activity's clock (the period on
/// the first update). updateHook allocates nothing.
class SimulatedServoRobotBase : public core::Component {
 public:
  ~SimulatedServoRobotBase() override;

 protected:
  SimulatedServoRobotBase(std::string name, std::string doc, SimulatedRobotDefaults defaults);
  /// The robot's kinematics (tool = its own tool point, base = its own base).
  virtual std::unique_ptr<kinematics::KinematicsSolver> makeSolver() const = 0;

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  double stepLength() noexcept;
  /// Commands `world_target` to be reached within dt (s; <= 0: the activity's period).
  void commandCartesian(const KDL::Frame& world_target, double dt) noexcept;
  void publish(double dt) noexcept;

  SimulatedRobotDefaults defaults_;

  core::Property<KDL::Frame> base_frame_{"base_frame", KDL::Frame::Identity(), "m",
                                         "pose of the robot base in the world frame"};
  core::Property<KDL::Frame> tool_frame_{"tool_frame", KDL::Frame::Identity(), "m",
                                         "pose of the tool in the frame of the kinematics' tool point"};
  core::Property<std::vector<double>> initial_joints_{"initial_joints", defaults_.initial_joints, "rad, m",
                                                      "joint positions at configure, one per joint"};
  core::Property<double> time_constant_{"time_constant", 0.01, "s", "first-order servo lag of every joint, > 0"};
  core::Property<std::vector<double>> max_velocity_{
      "max_velocity", {}, "rad/s, m/s", "velocity limit per joint (empty: the robot's defaults)"};
  core::Property<std::vector<double>> encoder_counts_{
      "encoder_counts",
      {},
      "1/rev, 1/m",
      "encoder counts per revolution / per metre per joint (empty: defaults; 0 = exact)"};
  core::Property<std::string> sensor_{"sensor", defaults_.sensor, "",
                                      "force/torque sensor preset: atiNano17, atiNano43 or ftSens"};
  core::Property<KDL::Wrench> sensor_bias_{"sensor_bias", KDL::Wrench::Zero(), "N, N·m",
                                           "offset the sensor adds to the true wrench"};
  core::Property<double> sensor_cutoff_{"sensor_cutoff", 0.0, "Hz", "sensor low-pass cutoff, >= 0 (0 = none)"};
  core::Property<int> seed_{"seed", 1, "1", "seed of the sensor noise: identical seeds give identical traces"};
  core::Property<double> twist_timeout_{"twist_timeout", 0.1, "s", "a desTwist is applied for this long, > 0"};

  core::InputPort<KDL::Frame> des_cart_pose_{
      "desCartPose",
      "desired tool pose, world frame; refused (last valid command held; e_ik_discontinuity) unless reachable on the "
      "current IK branch within max_velocity x step length on every joint, or e_ik_failed when out of reach",
      "m"};
  core::InputPort<KDL::JntArray> des_joint_position_{"desJointPosition", "desired joint positions", "rad, m"};
  core::InputPort<KDL::Wrench> contact_wrench_{
      "contactWrench", "simulation only: true wrench on the tool, world orientation, at the tool point", "N, N·m"};
  core::OutputPort<KDL::Frame> meas_cart_pose_{"measCartPose", "measured tool pose (encoders), world frame", "m"};
  core::OutputPort<KDL::JntArray> meas_joint_position_{"measJointPosition", "measured joint positions (encoders)",
                                                       "rad, m"};
  core::OutputPort<KDL::Wrench> meas_wrench_{"measWrench", "force/torque sensor reading, tool frame, at the tool point",
                                             "N, N·m"};
  core::OutputPort<KDL::Frame> true_cart_pose_{"trueCartPose", "simulation only: true tool pose, world frame", "m"};
  core::InputPort<KDL::Twist> des_twist_{
      "desTwist",
      "desired tool twist, world orientation, at the tool point; each step's pose obeys the rule of desCartPose",
      "m/s, rad/s"};
  core::OutputPort<KDL::Twist> meas_twist_{"measTwist", "measured tool twist, world orientation, at the tool point",
                                           "m/s, rad/s"};

  std::unique_ptr<kinematics::KinematicsSolver> solver_;
  std::optional<sim::ServoRobot> robot_;
  std::optional<sim::CartesianServo> servo_;
  std::optional<sim::ForceTorqueSensor> sensor_model_;
  KDL::JntArray joint_command_;
  KDL::Frame commanded_pose_, measured_pose_, previous_pose_, true_pose_;  // previous_pose_: true, last step
  KDL::Frame fk_true_pose_;  // the true pose of the joints true_fk_ holds
  /// The joints of a pose computed last and whether their forward kinematics succeeded: publish
  /// computes a pose again only for other joints.
  struct LastForward {
    KDL::JntArray joints;
    bool ok = false;
    bool known = false;
    void reset(unsigned n) {
      joints.resize(n);
      known = ok = false;
    }
    /// True when `q` is what was computed last (exactly); otherwise remembers it (no allocation).
    bool same(const KDL::JntArray& q) noexcept {
      if (known && q.data == joints.data) return true;
      joints.data = q.data;
      known = true;
      return false;
    }
  };
  LastForward measured_fk_, true_fk_;
  KDL::Twist twist_command_;
  std::int64_t last_update_ns_ = -1;
  std::int64_t twist_until_ns_ = -1;
  bool refusing_ = false;             // the last Cartesian command was refused
  bool told_failed_ = false;          // e_ik_failed emitted in this refusal episode
  bool told_discontinuity_ = false;   // e_ik_discontinuity emitted in this refusal episode
};

/// The I-SUR puncturing robot (thesis §4.3.1, 8 DOF: linear delta q1..q3 (m), base rotation q4,
/// micro arm q5..q8 (rad); kinematics::IsurPuncturingSolver, tool point = needle tip, x = needle
/// axis) with an ATI Nano17 at the needle. Defaults (ASSUMPTIONS, the thesis gives none): start
/// [0.1, 0.1, 0.1 m, 0, 0, 0.6, 0.6, 0 rad] (needle pointing down, away from the gimbal lock);
/// 0.1 m/s on the sliders, 1.5 rad/s on the revolute joints; encoders 1e6 counts/m (1 µm) and
/// 2^18 counts/rev.
class SimulatedISURRobot : public SimulatedServoRobotBase {
 public:
  explicit SimulatedISURRobot(std::string name);

 protected:
  std::unique_ptr<kinematics::KinematicsSolver> makeSolver() const override;
};

/// The UR5 holding the ultrasound probe (thesis §4.3.2; kinematics::Ur5Solver, tool point = the
/// flange: set tool_frame to the probe face), with desTwist / measTwist and an ATI Nano43
/// behind the probe. Defaults: start [0, -1.57, 1.57, -1.57, -1.57, 0] rad; 3.14 rad/s (the
/// thesis table's 180°/s); encoders 2^18 counts/rev (ASSUMPTION).
class SimulatedUR5Robot : public SimulatedServoRobotBase {
 public:
  explicit SimulatedUR5Robot(std::string name);

 protected:
  std::unique_ptr<kinematics::KinematicsSolver> makeSolver() const override;
};

}  // namespace cobra::components
