#pragma once
/// @file
/// Simulated robot bridges (thesis §4.5.7 I-SUR Robot Bridge, §4.5.8 UR5 Robot Bridge, §5.3 the
/// two-armed I-SUR) backed by cobra::sim: a stiff position-controlled robot (sim::ServoRobot:
/// first-order lag, joint position and velocity limits, encoder quantisation) of one or more tools,
/// commanded in joint or Cartesian space (through the robot's closed-form kinematics with the
/// continuity rule of kinematics::ContinuousIk), with a simulated force/torque sensor at each
/// tool. Same ports as the network bridges, so a deployment swaps one for the other by changing
/// only the component type.

#include <cstdint>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cobra/core/bounded_string.hpp"
#include "cobra/core/component.hpp"
#include "cobra/core/event.hpp"
#include "cobra/core/triple_buffer.hpp"
#include "cobra/kinematics/kinematics_solver.hpp"
#include "cobra/sim/ft_sensor.hpp"
#include "cobra/sim/servo.hpp"

namespace cobra::components {

/// The names of one tool's ports and properties and its sensor's default.
struct SimulatedToolDefaults {
  /// Between the ports' verb and noun: "" gives desCartPose, measCartPose, trueCartPose,
  /// measWrench, contactWrench; "Right" gives desRightCartPose, ..., contactRightWrench.
  std::string port_infix;
  /// Before the tool's property names: "" gives tool_frame, sensor, sensor_bias; "right_" gives
  /// right_tool_frame, right_sensor, right_sensor_bias.
  std::string property_prefix;
  std::string sensor;  ///< default preset: atiNano17, atiNano43 or ftSens
  std::string what;    ///< the kinematics' tool point, for the port docs ("the needle tip")
};

/// What distinguishes one simulated robot from another: its joints' defaults and its tools.
struct SimulatedRobotDefaults {
  std::string robot;                        ///< "I-SUR", "UR5": used in messages
  std::vector<double> initial_joints;       ///< rad / m
  std::vector<double> max_velocity;         ///< rad/s, m/s per joint
  std::vector<double> encoder_counts;       ///< counts per rev (revolute) / per m (prismatic)
  std::vector<SimulatedToolDefaults> tools;  ///< one per tool, in the kinematics' order
  bool twist_ports = false;                 ///< desTwist / measTwist on tool 0 (UR5 §4.5.8)
};

/// The kinematics a simulated robot drives: every tool's pose from the joints, and the inverse
/// kinematics of all tools together under the continuity rule of kinematics::ContinuousIk (the
/// branch of the current joints, every joint within max_velocity · dt). Poses of the kinematics'
/// own tool points in its own base frame (m, rad). forward and solve are noexcept and allocate
/// nothing.
class SimulatedRobotKinematics {
 public:
  virtual ~SimulatedRobotKinematics() = default;
  virtual std::size_t toolCount() const noexcept = 0;
  /// Joint limits (rad / m), one per joint.
  virtual const kinematics::JointLimits& limits() const noexcept = 0;
  /// The toolCount() tool poses for joints `q`; `tools` untouched unless Ok.
  virtual kinematics::IkStatus forward(const KDL::JntArray& q, std::span<KDL::Frame> tools) noexcept = 0;
  /// Sets the rule's velocity limits (one per joint, rad/s, m/s) and default dt (s).
  /// @throws std::invalid_argument naming the robot and the joint.
  virtual void setContinuity(const std::vector<double>& max_velocity, double period) = 0;
  /// Joints putting every tool at its target (toolCount() poses) with the rule from `current`
  /// within `dt` s; Discontinuous when refused by the rule, the solver's failure otherwise; `q_out`
  /// untouched unless Ok.
  virtual kinematics::IkStatus solve(std::span<const KDL::Frame> targets, const KDL::JntArray& current, double dt,
                                     KDL::JntArray& q_out) noexcept = 0;
};

/// Bridge component of one or more tools (SimulatedRobotDefaults::tools). Frames: every pose port
/// is a tool pose in the world frame (m, rad): world_T_tool = base_frame · FK(q) · tool_frame,
/// where FK is the robot's kinematics to that tool's own tool point (I-SUR: the needle tip, x =
/// needle axis; UR5: the flange; two-armed I-SUR: the Endo Stitch tip and the gripper).
/// Port and property names per tool carry the tool's infix / prefix (SimulatedToolDefaults); the
/// names below are the single-tool robots'.
///
/// Inputs: `desJointPosition` (KDL::JntArray, rad / m) and `desCartPose` of each tool (KDL::Frame,
/// m): a new joint command or a new Cartesian command of any tool becomes the servo command (both
/// new in one step: the joint command wins; a joint command of the wrong size is ignored). A
/// command with a non-finite value (a joint, a pose that is not a finite rigid frame, a twist) never
/// reaches the servo: the last valid command holds, and `e_command_not_finite` is emitted once per
/// episode (again after a valid command). A Cartesian command solves every tool together: the tools with a new command
/// go to it, the others keep their current commanded pose (the last accepted Cartesian command, or
/// the pose of the last joint command). It is turned into joints with the continuity rule of
/// kinematics::ContinuousIk, from the robot's current joint command (its set point): the solution
/// must lie on the IK branch of that command and differ from it by at most max_velocity · dt on
/// every joint (dt: the step length). A command the IK cannot reach (`e_ik_failed`) or that fails
/// the rule (`e_ik_discontinuity`: e.g. a pose across a wrist singularity, a branch flip, a jump)
/// is refused: the last valid command is held and nothing swings. Each event is emitted once per
/// refusal episode; `e_ik_solved` when a Cartesian command is accepted again. In each step that
/// refuses a command, `heldCartPose` of every tool (KDL::Frame, m, world frame; per tool with its
/// infix) carries the pose the tool holds (its last accepted command, which the measured pose
/// settles on within the servo's lag). Wired to the held-pose inputs of whatever produces the
/// commands (VariableAdmittance's heldPose, CartesianTrajectoryGenerator's heldPose_i), the
/// producers re-sync to it and the next command starts where the robot is (ARCHITECTURE §7).
/// `speed_scaling` (0.001 <= s <= 1, default 1, changed at run time: a UR's speed slider or reduced
/// mode) scales the velocity limits of the continuity rule: a command the scaled limits cannot
/// reach in one step is refused as above. `contactWrench`
/// of each tool (KDL::Wrench, N, N·m; simulation only): the true wrench the environment applies to
/// the tool, world orientation, reference point at the tool point (PatientSimulator's needleWrench
/// / probeWrench). With `twist_ports`: `desTwist` (KDL::Twist, m/s, rad/s, world orientation,
/// reference point at tool 0) integrated onto tool 0's commanded pose each step until a newer
/// pose/joint command or for `twist_timeout` s after the last twist received.
///
/// Outputs each update: `measJointPosition` (encoder reading, rad / m) and per tool
/// `measCartPose` (FK of the encoder reading, m), `measWrench` (the tool's simulated sensor's
/// reading of its contactWrench expressed in the tool frame, reference point at the tool point, N,
/// N·m), `trueCartPose` (simulation only: FK of the true joint position, m: what the physics
/// models must use); with `twist_ports` `measTwist` (m/s, rad/s, world orientation, tool 0's
/// point: the motion of the true pose over the step, as a controller computes it from joint
/// velocities rather than from encoder differences).
///
/// Properties: `base_frame` (m); per tool `tool_frame` (m), `sensor` (preset), `sensor_bias` (N,
/// N·m); `initial_joints` (rad, m), `time_constant` (s), `max_velocity` (rad/s, m/s),
/// `encoder_counts` (1/rev, 1/m), `sensor_cutoff` (Hz, every tool's sensor), `seed` (tool i's
/// sensor noise is seeded with seed + i).
///
/// The step length is the time since the previous update on the activity's clock (the period on
/// the first update). updateHook allocates nothing.
class SimulatedServoRobotBase : public core::Component {
 public:
  ~SimulatedServoRobotBase() override;

 protected:
  SimulatedServoRobotBase(std::string name, std::string doc, SimulatedRobotDefaults defaults);
  /// The robot's kinematics (its own tool points, its own base), one pose per tool of the defaults.
  virtual std::unique_ptr<SimulatedRobotKinematics> makeKinematics() const = 0;

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  /// One tool's properties, ports, sensor and poses (world frame, m).
  struct Tool {
    explicit Tool(const SimulatedToolDefaults& defaults);
    core::Property<KDL::Frame> tool_frame;
    core::Property<std::string> sensor;
    core::Property<KDL::Wrench> sensor_bias;
    core::InputPort<KDL::Frame> des_cart_pose;
    core::InputPort<KDL::Wrench> contact_wrench;
    core::OutputPort<KDL::Frame> meas_cart_pose;
    core::OutputPort<KDL::Wrench> meas_wrench;
    core::OutputPort<KDL::Frame> true_cart_pose;
    core::OutputPort<KDL::Frame> held_cart_pose;
    std::optional<sim::ForceTorqueSensor> sensor_model;
    KDL::Frame commanded, measured, previous, true_pose;  // previous: true, last step
    KDL::Frame fk_true;  // the true pose of the joints true_fk_ holds
  };
  double stepLength() noexcept;
  /// Commands targets_ (world frame, one per tool) to be reached within dt (s; at least the
  /// activity's period).
  void commandCartesian(double dt) noexcept;
  /// The commanded poses from the robot's joint command (after a joint command).
  void commandedFromJoints() noexcept;
  void publish(double dt) noexcept;
  KDL::Frame toWorld(std::size_t tool, const KDL::Frame& fk) const noexcept;

  SimulatedRobotDefaults defaults_;
  std::vector<std::unique_ptr<Tool>> tools_;  // fixed at construction (ports and properties point into them)

  core::Property<KDL::Frame> base_frame_{"base_frame", KDL::Frame::Identity(), "m",
                                         "pose of the robot base in the world frame"};
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
  core::Property<double> sensor_cutoff_{"sensor_cutoff", 0.0, "Hz",
                                        "low-pass cutoff of every tool's sensor, >= 0 (0 = none)"};
  core::Property<int> seed_{"seed", 1, "1",
                            "seed of the sensor noise (tool i: seed + i): identical seeds give identical traces"};
  core::Property<double> twist_timeout_{"twist_timeout", 0.1, "s", "a desTwist is applied for this long, > 0"};
  core::Property<double> speed_scaling_{"speed_scaling", 1.0, "1",
                                        "fraction of max_velocity a Cartesian command may use (0.001..1; run time)"};

  core::InputPort<KDL::JntArray> des_joint_position_{"desJointPosition", "desired joint positions", "rad, m"};
  core::OutputPort<KDL::JntArray> meas_joint_position_{"measJointPosition", "measured joint positions (encoders)",
                                                       "rad, m"};
  core::InputPort<KDL::Twist> des_twist_{
      "desTwist",
      "desired tool twist, world orientation, at the tool point; each step's pose obeys the rule of desCartPose",
      "m/s, rad/s"};
  core::OutputPort<KDL::Twist> meas_twist_{"measTwist", "measured tool twist, world orientation, at the tool point",
                                           "m/s, rad/s"};

  std::unique_ptr<SimulatedRobotKinematics> kinematics_;
  std::optional<sim::ServoRobot> robot_;
  double default_dt_ = 1e-3;             // s: the activity's period (1 ms without one)
  KDL::JntArray joint_command_, solution_;
  std::vector<KDL::Frame> targets_;      // world frame, one per tool
  std::vector<KDL::Frame> solve_targets_, fk_;  // robot frame, one per tool (preallocated)
  /// The joints of poses computed last and whether their forward kinematics succeeded: publish
  /// computes poses again only for other joints.
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
  std::int64_t last_pose_command_ns_ = -1;  // when the last desired pose was read (-1: none since start)
  std::int64_t twist_until_ns_ = -1;
  bool refusing_ = false;             // the last Cartesian command was refused
  bool told_failed_ = false;          // e_ik_failed emitted in this refusal episode
  bool told_discontinuity_ = false;   // e_ik_discontinuity emitted in this refusal episode
  bool told_not_finite_ = false;      // e_command_not_finite emitted in this episode
  /// Emits e_command_not_finite once per episode (refused: a command sample was not finite).
  void refuseNotFinite() noexcept;
  /// The first refused command of the last refusal episode, published by the update (a copy
  /// into a triple buffer: no allocation, no lock) for lastFailure(), which words it on the
  /// caller's thread.
  struct Refusal {
    bool any = false;
    double t = 0.0;                   // s, the component's time
    kinematics::IkStatus status = kinematics::IkStatus::Ok;
    std::size_t tool = 0;             // the first tool whose pose moved (0 when none did)
    KDL::Frame pose, held;            // world, m: the refused pose, and the pose the robot holds
  };
  core::TripleBuffer<Refusal> refusal_{Refusal{}};
  mutable std::mutex refusal_reader_;  // lastFailure's callers take turns: the buffer has one reader
  /// "at T s UR5 refused tool 0's pose (x, y, z) m, rpy (r, p, y) deg: out of reach (no IK
  /// solution); it holds (x, y, z) m" — the operation `lastFailure` (for `cobra run`'s safe stop),
  /// run on the caller's thread.
  std::string lastFailure();
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
  std::unique_ptr<SimulatedRobotKinematics> makeKinematics() const override;
};

/// The UR5 holding the ultrasound probe (thesis §4.3.2; kinematics::Ur5Solver, tool point = the
/// flange: set tool_frame to the probe face), with desTwist / measTwist and an ATI Nano43
/// behind the probe. Defaults: start [0, -1.57, 1.57, -1.57, -1.57, 0] rad; 3.14 rad/s (the
/// thesis table's 180°/s); encoders 2^18 counts/rev (ASSUMPTION).
class SimulatedUR5Robot : public SimulatedServoRobotBase {
 public:
  explicit SimulatedUR5Robot(std::string name);

 protected:
  std::unique_ptr<SimulatedRobotKinematics> makeKinematics() const override;
};

/// The two-armed I-SUR of the suturing task (thesis §5.3, 14 DOF; kinematics::IsurSuturingSolver,
/// joints in its order: linear delta q1..q3 (m), base rotation q4, the 4-DOF right micro arm
/// q5..q8 holding the Endo Stitch, the 6-DOF left micro arm q9..q14 with a gripper holding a
/// stick (rad)). Two tools: Right = the Endo Stitch tip (ports desRightCartPose,
/// measRightCartPose, trueRightCartPose, measRightWrench, contactRightWrench; properties
/// right_tool_frame, right_sensor (default atiNano43, §5.3.2), right_sensor_bias) and Left = the
/// stick's tip (the same with Left / left_; the gripper's frame from the kinematics: set
/// left_tool_frame to the stick's tip; left_sensor default atiNano17). Cartesian commands of
/// both tools are solved together by the split IK of §5.4.1 (the macro + Endo Stitch arm first,
/// then the 6-DOF arm from the platform pose) with the continuity rule on each sub-structure
/// (kinematics::ContinuousIsurSuturingIk).
///
/// Endo Stitch actuation: the event named by `actuate_event` (default "e_actuate_endo_stitch") on
/// the event port `inputEvents` actuates the Endo Stitch (the needle passes from one jaw to the
/// other) over `actuation_time` s (default 0.3); when done, `endoStitchActuations` (int, completed
/// actuations since configure, written every update) increments and `e_endo_stitch_actuated` is
/// emitted on `events`. A request during an actuation is refused with `e_endo_stitch_busy`; other
/// events are ignored; requests sent before start are dropped.
///
/// Defaults (ASSUMPTIONS, the thesis gives none): start [0.1, 0.1, 0.1 m, 0, 0, 0.75, 0.45, 0,
/// 0, 0.5, -0.5, 0, 0.5, 0 rad]: the Endo Stitch pitched 1.2 rad down (0.37 rad from its vertical,
/// the elbow q6 - q7 on the solver's 0.3 rad rule), the 6-DOF arm's elbow bent 1 rad and its wrist
/// 0.5 rad from alignment (both away from their singularities); with the suturing application's scene's
/// base (1 m above the table, z up) the Endo Stitch tip is at (0.18, 0, 0.17) m and the gripper at
/// (0.07, 0.12, 0.31) m. Velocities, encoders as SimulatedISURRobot's for q1..q8 and 1.5 rad/s,
/// 2^18 counts/rev for q9..q14.
class SimulatedISURSuturingRobot : public SimulatedServoRobotBase {
 public:
  explicit SimulatedISURSuturingRobot(std::string name);

 protected:
  std::unique_ptr<SimulatedRobotKinematics> makeKinematics() const override;
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

 private:
  core::Property<std::string> actuate_event_{"actuate_event", "e_actuate_endo_stitch", "",
                                             "event that actuates the Endo Stitch (1 to 63 characters)"};
  core::Property<double> actuation_time_{"actuation_time", 0.3, "s",
                                         "time for the needle to pass from one jaw to the other, > 0"};
  core::InputPort<core::Event> input_events_{"inputEvents", "Endo Stitch actuation requests (actuate_event)", ""};
  core::OutputPort<int> actuations_{"endoStitchActuations", "completed Endo Stitch actuations since configure",
                                    "1"};
  core::BoundedString<63> actuate_name_;
  std::int64_t actuation_done_ns_ = -1;  // clock time the running actuation completes; -1: idle
  int completed_ = 0;
};

}  // namespace cobra::components
