#pragma once
/// @file
/// Kinematics of the I-SUR robot (thesis §4.3.1, §5.3.1, §5.4.1): a macro unit — a linear delta
/// (joints q1..q3, prismatic, m) turned about the vertical by a revolute joint at the base of the
/// parallel structure (q4, rad) — carrying 4-DOF micro arms (all revolute, rad).
///  - Puncturing setup (8 DOF): one micro arm (q5..q8) holding the needle.
///  - Suturing setup (14 DOF): the same macro and 4-DOF arm (holding the Endo Stitch) plus a 6-DOF
///    micro arm with a gripper (q9..q14), mounted on the same platform.
///
/// Kinematic model (frames; all lengths in `IsurGeometry`):
///   T_needle = Rz(q4) · Trans(p_delta(q1, q2, q3)) · Trans(mount) · Rz(q5) · Trans(shoulder)
///              · Ry(q6) · Tx(upper_arm) · Ry(q7) · Tx(forearm) · Rx(q8) · Trans(tool)
/// so that the needle's orientation in ZYX Euler angles is yaw = q4 + q5, pitch = q6 + q7,
/// roll = q8 — the relations the thesis states for this arm (§5.4.1). The needle axis is the x axis
/// of the tool frame (the roll axis). The thesis gives the joint structure but no dimensions: the
/// lengths below are documented plausible values for a surgical micro arm, to be replaced by the
/// robot's calibration.
///
/// Inverse kinematics: the thesis' decomposition (§5.4.1). The orientation fixes yaw, pitch and
/// roll; the redundancy (how yaw splits between q4 and q5, pitch between q6 and q7) is resolved
/// around the seed by fixed shares, clamped to the joint limits — so the solution is a continuous
/// function of target and seed, which is why the thesis chose it for sampling-based planning
/// (neighbouring samples give neighbouring configurations, "equivalent to a closed form"). Then the
/// micro arm's offset is known and the linear delta's closed-form inverse places the platform.
/// Where the delta cannot (a slider at its end, e.g. deep in an insertion), the pitch split moves
/// to the nearest one (to the shares' choice) for which it can: the elbow takes over what the
/// delta lacks, continuously along a path.
/// In the suturing setup the 4-DOF arm (priority: it can only be translated by the macro) is solved
/// first; the platform pose then is the base of the 6-DOF arm, solved in closed form (Puma-type
/// arm: Puma260Solver with the micro arm's lengths).

#include <array>
#include <span>
#include <string_view>

#include <kdl/chain.hpp>
#include <kdl/frames.hpp>

#include "cobra/kinematics/kinematics_solver.hpp"
#include "cobra/kinematics/linear_delta.hpp"
#include "cobra/kinematics/puma260.hpp"

namespace cobra::kinematics {

/// The 4-DOF micro arm (m). Directions are in the frame of the joint before each element.
struct IsurMicroArm {
  KDL::Vector mount = KDL::Vector(0.0, 0.0, -0.08);     ///< q5 axis origin from the platform origin, m
  KDL::Vector shoulder = KDL::Vector(0.0, 0.0, -0.05);  ///< q5 frame to the q6 axis, m
  double upper_arm = 0.12;                              ///< q6 axis to q7 axis, along x, m
  double forearm = 0.10;                                ///< q7 axis to q8 axis, along x, m
  KDL::Vector tool = KDL::Vector(0.15, 0.0, 0.0);       ///< q8 frame to the needle tip (along x: the needle), m
};

/// Geometry and joint limits of the I-SUR robot in its puncturing setup, plus the redundancy shares.
struct IsurGeometry {
  LinearDeltaGeometry macro = LinearDeltaGeometry::isurMacro();
  IsurMicroArm micro;
  /// Limits of q4..q8 (rad): base revolute ±170°, micro yaw ±90°, the two pitch joints ±100°,
  /// roll ±180° (plausible values; the thesis gives none).
  std::array<double, 5> lower = {-2.967, -1.571, -1.745, -1.745, -3.1416};
  std::array<double, 5> upper = {2.967, 1.571, 1.745, 1.745, 3.1416};
  /// Share of a yaw change (q4 + q5) taken by the base revolute q4, the rest by q5. 0: the heavy
  /// macro base holds still and the micro yaw joint turns.
  double yaw_share = 0.0;
  /// Share of a pitch change (q6 + q7) taken by q6, the rest by q7 (when pitch_difference is NaN).
  double pitch_share = 0.5;
  /// The preferred elbow q6 - q7 (rad). Finite: the pitch splits as q6 - q7 = pitch_difference
  /// wherever the delta can place the platform, else the nearest difference for which it can: the
  /// split is a function of the target pose alone (not of the seed), so a path that goes deep
  /// (the delta at the end of its stroke) and comes back returns the elbow to it, and a planner
  /// sampling joints agrees with the control path. NaN: split by pitch_share around the seed.
  /// 0.3 rad is the puncturing setup's (world.lua initial joints: q6 = 0.85, q7 = 0.55).
  double pitch_difference = 0.3;
  /// The preferred base turntable angle q4 (rad). Finite: the yaw q4 + q5 is turned by the micro
  /// yaw q5 with the base at base_angle, the base taking only what q5's limits cannot (nearest to
  /// base_angle): a function of the target's yaw alone, so the base comes back when the yaw does.
  /// NaN: split by yaw_share around the seed.
  double base_angle = 0.0;
};

/// The puncturing robot as a KDL chain with the delta replaced by three Cartesian joints, joints
/// [q4, x, y, z, q5, q6, q7, q8] (rad, m): the same kinematics when x, y, z are the delta's platform
/// position. For cross-checks and for KDL's solvers (the delta itself is not a serial chain).
KDL::Chain cartesianMacroChain(const IsurMicroArm& micro);

/// The I-SUR puncturing robot: 8 joints [q1 q2 q3 (m), q4 .. q8 (rad)], tool = needle tip.
/// `forward`/`inverse` are noexcept and allocate nothing.
class IsurPuncturingSolver final : public KinematicsSolver {
 public:
  static constexpr unsigned kJoints = 8;
  /// |cos(pitch)| below this is the band around the wrist's gimbal lock (pitch ±90°, the needle
  /// vertical) where the target's yaw is ill-conditioned: inverse keeps the seed's yaw q4 + q5 and
  /// follows the target's tilt in that yaw plane only (the tilt across it, at most 1e-3 rad =
  /// 0.06°, is not followed), so a tilt noise of 1e-9 rad (rounding in an admittance's output)
  /// turns the yaw by at most 1e-6 rad instead of up to π.
  static constexpr double kWristBand = 1e-3;
  /// The branch (wrist representation) of a pitch q6 + q7 (rad): what branch() reports.
  static IkBranch pitchBranch(double pitch) noexcept;
  /// The base angle q4 (rad) the redundancy rule gives for the yaw q4 + q5 (rad): base_angle as far
  /// as the limits of q4 and q5 allow (needs a finite geometry().base_angle).
  double baseOnRule(double yaw) const noexcept;

  /// @throws std::invalid_argument naming the element ("I-SUR: joint 5 limits [1, 0] rad: min must
  /// be <= max", "I-SUR: parameter yaw_share is 2: give a value in [0, 1]", delta errors...).
  explicit IsurPuncturingSolver(const IsurGeometry& geometry = IsurGeometry{}, std::string_view name = "I-SUR");

  std::string_view name() const noexcept override { return name_; }
  unsigned jointCount() const noexcept override { return kJoints; }
  const JointLimits& limits() const noexcept override { return limits_; }
  const IsurGeometry& geometry() const noexcept { return geometry_; }
  const LinearDeltaSolver& macro() const noexcept { return delta_; }

  IkStatus forward(const KDL::JntArray& q, KDL::Frame& pose) noexcept override;
  /// Pose of the delta platform in the robot base frame after the base revolute (the macro unit's
  /// end effector: Rz(q4)·Trans(p_delta)); the suturing setup mounts its second arm on it.
  IkStatus platformPose(const KDL::JntArray& q, KDL::Frame& pose) const noexcept;
  /// Number of frames linkFrames() writes.
  static constexpr unsigned kLinks = 6;
  /// Every link frame in the robot base frame (m, rad), the order of the puncturing scene file:
  /// [0] turntable Rz(q4), [1] delta platform Rz(q4)·Trans(p_delta), [2] micro yaw frame (after
  /// q5, origin at the mount), [3] upper arm (after q6, origin on the q6 axis, arm along x),
  /// [4] forearm (after q7, on the q7 axis, along x), [5] needle tip (after q8 and the tool; the
  /// needle runs along -x from it). [5] equals forward(q). `frames` untouched unless Ok; BadInput
  /// when q or frames has the wrong size. No allocation.
  IkStatus linkFrames(const KDL::JntArray& q, std::span<KDL::Frame> frames) const noexcept;
  /// The decomposition described in the file comment. Both ZYX representations of the target
  /// orientation (pitch θ and π - θ) are tried; the valid one nearest the seed wins. At the gimbal
  /// lock (pitch ±90°) roll keeps the seed's q8. Unreachable when the delta cannot place the
  /// platform; JointLimits when the orientation or the delta needs joints outside their limits.
  IkStatus inverse(const KDL::Frame& target, const KDL::JntArray& seed, KDL::JntArray& q_out) noexcept override;

  /// The I-SUR's only discrete choice is the ZYX representation of the needle orientation: bit 0
  /// set when cos(q6 + q7) < 0 (pitch beyond ±90°: the representation (yaw + π, π - pitch, roll + π)).
  /// Its boundary, pitch ±90° (the needle axis along the base axis q4: the yaw and roll axes
  /// align), is the wrist singularity: there the bit is ambiguous. The yaw and pitch splits are
  /// continuous (no branches), and so is the delta's solution. Crossing the boundary within one
  /// branch turns yaw and roll by π, which is why a Cartesian command across the vertical needle
  /// is refused (see ContinuousIk).
  IkBranch branch(std::span<const double> q) const noexcept override;
  /// `inverse` among the representations on `branch`; Discontinuous when only the other fits.
  IkStatus inverseOnBranch(const KDL::Frame& target, const KDL::JntArray& seed, IkBranch branch,
                           KDL::JntArray& q_out) noexcept override;

 private:
  /// One wrist representation; `search_elbow`: where the delta cannot reach with the preferred
  /// split, search the nearest split it can (else return its failure).
  IkStatus solveCandidate(const KDL::Frame& target, double yaw, double pitch, double roll, const KDL::JntArray& seed,
                          std::array<double, kJoints>& q, bool search_elbow) const noexcept;
  /// The delta's sliders q[0..2] placing the platform for the micro joints q[3..7] (closed form).
  IkStatus placePlatform(const KDL::Frame& target, std::array<double, kJoints>& q) const noexcept;
  KDL::Frame microForward(double q5, double q6, double q7, double q8) const noexcept;

  IsurGeometry geometry_;
  std::string name_;
  LinearDeltaSolver delta_;
  JointLimits limits_;
};

/// Geometry of the suturing setup: the puncturing robot (its micro arm holds the Endo Stitch) and
/// the 6-DOF gripper arm, a Puma-type arm whose DH frame 0 sits at `left_mount` on the platform.
struct IsurSuturingGeometry {
  IsurGeometry right;
  /// Plausible micro-arm lengths (m): d1 0, a2 0.12, a3 0, d3 0.02, d4 0.10, d6 0.08.
  Puma260Parameters left = Puma260Parameters{.d1 = 0.0, .a2 = 0.12, .a3 = 0.0, .d3 = 0.02, .d4 = 0.10, .d6 = 0.08};
  /// ±170° on every joint of the 6-DOF arm, rad.
  JointLimits left_limits = revoluteLimits(6, -2.967, 2.967);
  /// Pose of the 6-DOF arm's DH frame 0 in the platform frame: 0.1 m beside the 4-DOF arm, z down.
  KDL::Frame left_mount = KDL::Frame(KDL::Rotation::RotX(3.141592653589793), KDL::Vector(0.0, 0.10, -0.08));
};

/// The I-SUR suturing robot: 14 joints [q1..q8 as IsurPuncturingSolver, q9..q14 the 6-DOF arm];
/// two tools: the Endo Stitch tip (4-DOF arm) and the gripper (6-DOF arm). Not a KinematicsSolver
/// (two end effectors). No allocation on `forward`/`inverse`.
class IsurSuturingSolver {
 public:
  static constexpr unsigned kJoints = 14;

  /// @throws std::invalid_argument as IsurPuncturingSolver and Puma260Solver (named "I-SUR left arm").
  explicit IsurSuturingSolver(const IsurSuturingGeometry& geometry = IsurSuturingGeometry{});

  const JointLimits& limits() const noexcept { return limits_; }
  const IsurPuncturingSolver& rightStructure() const noexcept { return right_; }

  IkStatus forward(const KDL::JntArray& q, KDL::Frame& stitch_tool, KDL::Frame& gripper) noexcept;
  /// Number of frames linkFrames() writes.
  static constexpr unsigned kLinks = 12;
  /// Every link frame in the robot base frame, the order of the suturing scene file: [0..5] as
  /// IsurPuncturingSolver::linkFrames (5 = Endo Stitch tip), [6..10] the 6-DOF arm's DH frames
  /// after its joints 1..5, [11] the gripper (= forward's `gripper`). `frames` untouched unless
  /// Ok. No allocation.
  IkStatus linkFrames(const KDL::JntArray& q, std::span<KDL::Frame> frames) noexcept;
  /// §5.4.1: the macro + 4-DOF sub-structure first (priority to the Endo Stitch arm, which only the
  /// macro can translate), then the 6-DOF arm in closed form from the resulting platform pose.
  /// `q_out` (14) untouched unless Ok.
  IkStatus inverse(const KDL::Frame& stitch_target, const KDL::Frame& gripper_target, const KDL::JntArray& seed,
                   KDL::JntArray& q_out) noexcept;

  /// Joints of the macro + Endo Stitch sub-structure (q1..q8) and of the 6-DOF arm (q9..q14).
  static constexpr unsigned kRightJoints = IsurPuncturingSolver::kJoints;
  static constexpr unsigned kLeftJoints = 6;
  /// Bit of IkBranch::bits where the 6-DOF arm's branch bits start (bit 0 is the Endo Stitch arm's).
  static constexpr unsigned kLeftBranchShift = 1;
  /// The branch of a configuration (14 values, m / rad): bit 0 (and its ambiguity) the Endo Stitch
  /// sub-structure's wrist representation (IsurPuncturingSolver::branch: the pitch q6 + q7 beyond
  /// ±90°), bits 1..3 the 6-DOF arm's shoulder, elbow and wrist (Puma260Solver::branch of q9..q14,
  /// shifted by kLeftBranchShift). An empty IkBranch for a wrong-size `q`. No allocation.
  IkBranch branch(std::span<const double> q) const noexcept;
  /// `inverse` with each sub-structure on its part of `branch` (the split IK of §5.4.1 keeping the
  /// branch of the current configuration): the Endo Stitch sub-structure by
  /// IsurPuncturingSolver::inverseOnBranch, then the 6-DOF arm by Puma260Solver::inverseOnBranch
  /// from the platform pose that gives. Discontinuous when a sub-structure reaches its target only
  /// on another branch (e.g. the Endo Stitch across its vertical, the gripper arm's wrist flipped).
  /// `q_out` (14) untouched unless Ok. No allocation.
  IkStatus inverseOnBranch(const KDL::Frame& stitch_target, const KDL::Frame& gripper_target,
                           const KDL::JntArray& seed, IkBranch branch, KDL::JntArray& q_out) noexcept;
  /// The first step of the split IK alone: the macro + Endo Stitch joints q1..q8 putting the Endo
  /// Stitch at `stitch_target`, nearest `q`'s q1..q8 among the solutions on `right_branch`
  /// (IsurPuncturingSolver's bit, not shifted). `q_out` (14) = `q` with q1..q8 replaced (the
  /// gripper moves with the platform); untouched unless Ok. No allocation.
  IkStatus inverseEndoStitchArm(const KDL::Frame& stitch_target, const KDL::JntArray& q, IkBranch right_branch,
                                KDL::JntArray& q_out) noexcept;
  /// The branch bits of each sub-structure in a suturing IkBranch (not shifted).
  static IkBranch rightBranch(IkBranch branch) noexcept;
  static IkBranch leftBranch(IkBranch branch) noexcept;
  /// The second step of the split IK alone: the 6-DOF arm's joints q9..q14 putting the gripper at
  /// `gripper_target` from the platform of `q`'s macro joints, nearest `q`'s q9..q14 among the
  /// solutions on `left_branch` (Puma260Solver's bits, not shifted). `q_out` (14) = `q` with
  /// q9..q14 replaced; untouched unless Ok. No allocation.
  IkStatus inverseGripperArm(const KDL::Frame& gripper_target, const KDL::JntArray& q, IkBranch left_branch,
                             KDL::JntArray& q_out) noexcept;

 private:
  /// The 6-DOF arm for the platform of q_right_, seeded by seed_left_, into q_left_.
  IkStatus solveGripperArm(const KDL::Frame& gripper_target, IkBranch left_branch) noexcept;

  IsurPuncturingSolver right_;
  Puma260Solver left_;
  KDL::Frame left_mount_;
  JointLimits limits_;
  KDL::JntArray q_right_;
  KDL::JntArray seed_right_;
  KDL::JntArray q_left_;
  KDL::JntArray seed_left_;
};

}  // namespace cobra::kinematics
