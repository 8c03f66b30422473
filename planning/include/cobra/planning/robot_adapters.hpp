#pragma once
/// @file
/// RobotModel adapters around the cobra::kinematics solvers of the thesis' robots, in the link
/// order the scene files document (scene.hpp; e.g. planning/test/scenes/puncturing.scene):
///  - `Ur5Model`: the UR5 holding the ultrasound probe (puncturing, tool 1 of q), closed-form IK;
///  - `IsurPuncturingModel`: the 8-DOF I-SUR with the needle (puncturing, tool 0 of q);
///  - `IsurSuturingModel`: the two-armed 14-DOF I-SUR, ONE solver for both tools (Algorithm 5.1,
///    thesis §5.4.1).
/// solve() warm-starts from the previous solution when the tool poses moved less than 0.02 m and
/// 0.2 rad since the previous reachable call (a step along a path or a planner edge: neighbouring
/// states get neighbouring configurations, as in the thesis), and from the configured seed
/// otherwise (unrelated planner samples), so that a state's answer does not depend on the states
/// checked before it except along such a chain of small steps. resetWarmStart() forgets the
/// previous solution. solve() allocates nothing (all joint arrays are preallocated).
///
/// All three also offer the joint space the motion planner searches (RobotModel::jointCount() and
/// after): the planner searches joints (or the redundancy-resolved coordinates of the I-SUR) with
/// forward kinematics only, and turns goals into joints with the continuity-keeping IK the
/// control path uses (the start's branch).

#include <array>
#include <span>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/kinematics/isur.hpp"
#include "cobra/kinematics/ur5.hpp"
#include "cobra/planning/robot_model.hpp"
#include "cobra/planning/scene.hpp"
#include "cobra/planning/state_validator.hpp"

namespace cobra::planning {

/// The warm-start state the file comment describes, for a robot of `Tools` tools (1 or 2): the
/// configured seed, the last reachable solution and the tool poses it was for. No allocation
/// after construction.
template <std::size_t Tools>
class WarmStart {
 public:
  /// @throws std::invalid_argument naming `robot` unless `seed` holds `joints` finite values.
  WarmStart(unsigned joints, const KDL::JntArray& seed, const char* robot);
  /// The configured seed (the next solve() and every one after reset() start from it).
  /// @throws std::invalid_argument as the constructor.
  void setSeed(const KDL::JntArray& q);
  void reset() noexcept {
    seed_.data = initial_.data;
    has_previous_ = false;
  }
  /// The seed of a solve for `tools`: the previous solution when every tool moved less than
  /// 0.02 m and 0.2 rad since, the configured seed otherwise.
  const KDL::JntArray& seedFor(std::span<const KDL::Frame> tools) noexcept;
  /// Remembers the solution `q` reached for `tools`.
  void keep(const KDL::JntArray& q, std::span<const KDL::Frame> tools) noexcept;
  const KDL::JntArray& initial() const { return initial_; }
  /// The last reachable solution (the seed before any) [m, rad].
  const KDL::JntArray& joints() const { return seed_; }

 private:
  const char* robot_;
  KDL::JntArray initial_;
  KDL::JntArray seed_;
  std::array<KDL::Frame, Tools> previous_{};
  bool has_previous_ = false;
};

/// UR5 + probe. Links (base frame of the UR5): 0 base, 1..6 the DH frames after joints 1..6,
/// 7 the probe tip (probe axis = z of the flange).
/// Of the (up to 8) closed-form solutions solve() keeps the branch of the configured seed (shoulder,
/// elbow, wrist), so a state's validity does not depend on the states checked before it (the
/// nearest-to-the-previous-solution rule would switch branches between far-apart planner samples
/// and let a path's arm jump); the warm start picks each joint's 2π representative and θ6 at the
/// wrist singularity. A pose only another branch reaches is Unreachable.
class Ur5Model final : public RobotModel {
 public:
  /// Default probe: 0.12 m along the flange's z axis [m].
  static KDL::Frame defaultProbe() { return KDL::Frame(KDL::Vector(0.0, 0.0, 0.12)); }
  /// Default warm-start seed (rad): elbow up, probe pointing down, arm reaching along +x of the UR5
  /// base (the puncturing scene turns that towards the phantom).
  static KDL::JntArray defaultSeed();

  /// @param probe tip frame in the flange frame [m]
  /// @throws std::invalid_argument as kinematics::Ur5Solver, or for a seed that is not 6 finite values.
  explicit Ur5Model(const KDL::Frame& probe = defaultProbe(), const KDL::JntArray& seed = defaultSeed(),
                    const kinematics::Ur5Parameters& parameters = kinematics::Ur5Parameters{});

  std::size_t toolCount() const override { return 1; }
  std::size_t linkCount() const override { return 8; }
  Reachability solve(std::span<const KDL::Frame> tools_in_base, std::span<KDL::Frame> links_in_base) override;
  /// Back to the seed given at construction or by the last setSeed().
  void resetWarmStart() override { warm_.reset(); }

  /// Next solve() (and every one after resetWarmStart()) starts from `q` (6 joints, rad).
  /// @throws std::invalid_argument otherwise.
  void setSeed(const KDL::JntArray& q) { warm_.setSeed(q); }
  /// Joint values of the last reachable solve() (the seed before any) [rad].
  const KDL::JntArray& joints() const { return warm_.joints(); }
  kinematics::Ur5Solver& solver() { return solver_; }

  /// Velocity limit of every joint [rad/s]: the simulated UR5's (thesis table: 180°/s).
  static constexpr double kMaxJointVelocity = 3.14;
  std::size_t jointCount() const override { return 6; }
  void jointLimits(std::span<double> lower, std::span<double> upper, std::span<double> max_velocity) const override;
  bool linkFramesAt(std::span<const double> q, std::span<KDL::Frame> links_in_base) override;
  std::size_t toolLink(std::size_t) const override { return 7; }
  void seedJoints(std::span<double> q) const override;
  /// kinematics::Ur5Solver::inverseOnBranch on the branch of `seed` (Ur5Solver::branch: shoulder,
  /// the wrist point's side of the base axis; elbow, the sign of sin q3; wrist, the sign of sin q5),
  /// the solution nearest the seed: exactly what the control path's kinematics::ContinuousIk
  /// solves, so a path verified with it is one the robot follows without a branch change.
  Reachability inverseNear(std::span<const KDL::Frame> tools_in_base, std::span<const double> seed,
                           std::span<double> q) override;
  /// On the start's branch as kinematics::Ur5Solver::branch defines it (the rule of the control
  /// path's IK): the wrist point on the start's side of the base axis, at least kShoulderMargin from
  /// it (the lateral distance a2 c2 + a3 c23 + d5 s234, m: near it q1 turns fast for a small
  /// Cartesian step); sin q3 and sin q5 of the start's signs, at least kElbowMargin and kWristMargin
  /// from 0 (the stretched elbow, the aligned wrist). Each margin shrinks to half the start's or the
  /// goal's own distance when that is smaller.
  bool keepsBranch(std::span<const double> q, std::span<const double> start,
                   std::span<const double> goal) const override;
  static constexpr double kShoulderMargin = 0.05;  // m
  static constexpr double kElbowMargin = 0.1;      // sin q3 [1]
  static constexpr double kWristMargin = 0.1;      // sin q5 [1]
  /// The joint limits intersected with start ± π: a path never turns a joint more than half a turn
  /// from where it starts (the limits allow ±2π, which only adds detours to the search).
  void coordinateBounds(std::span<const double> start, std::span<const double> goal, std::span<double> lower,
                        std::span<double> upper) const override;

 private:
  /// Of solutions_, the one on the branch of `reference` (elbow, wrist, shoulder nearest), with
  /// each joint's representative nearest `near` written to `q`. Unreachable / OtherBranch if none.
  Reachability pickBranch(std::span<const double> reference, std::span<const double> near, std::span<double> q) const;

  kinematics::Ur5Solver solver_;
  kinematics::IkSolutionSet solutions_;
  WarmStart<1> warm_;
  KDL::JntArray q_;
  KDL::JntArray seed_;
};

/// I-SUR puncturing robot (8 DOF). Links: kinematics::IsurPuncturingSolver::linkFrames (0 turntable,
/// 1 delta platform, 2 micro yaw, 3 upper arm, 4 forearm, 5 needle tip, needle along -x from it).
class IsurPuncturingModel final : public RobotModel {
 public:
  /// Default warm-start seed: sliders at 0.1 m, the revolute joints at 0 but the elbow q6 - q7 =
  /// pitch_difference (on the solver's redundancy rule).
  static KDL::JntArray defaultSeed();

  explicit IsurPuncturingModel(const kinematics::IsurGeometry& geometry = kinematics::IsurGeometry{},
                               const KDL::JntArray& seed = defaultSeed());

  std::size_t toolCount() const override { return 1; }
  std::size_t linkCount() const override { return kinematics::IsurPuncturingSolver::kLinks; }
  Reachability solve(std::span<const KDL::Frame> tools_in_base, std::span<KDL::Frame> links_in_base) override;
  /// Back to the seed given at construction or by the last setSeed().
  void resetWarmStart() override { warm_.reset(); }

  /// Next solve() (and every one after resetWarmStart()) starts from `q` (8 joints, m and rad).
  /// @throws std::invalid_argument otherwise.
  void setSeed(const KDL::JntArray& q) { warm_.setSeed(q); }
  const KDL::JntArray& joints() const { return warm_.joints(); }
  kinematics::IsurPuncturingSolver& solver() { return solver_; }

  /// Velocity limits of the simulated I-SUR (components/sim): sliders [m/s], revolute joints [rad/s].
  static constexpr double kMaxSliderVelocity = 0.1;
  static constexpr double kMaxRevoluteVelocity = 1.5;
  std::size_t jointCount() const override { return kinematics::IsurPuncturingSolver::kJoints; }
  void jointLimits(std::span<double> lower, std::span<double> upper, std::span<double> max_velocity) const override;
  bool linkFramesAt(std::span<const double> q, std::span<KDL::Frame> links_in_base) override;
  std::size_t toolLink(std::size_t) const override { return 5; }
  void seedJoints(std::span<double> q) const override;
  /// kinematics::IsurPuncturingSolver::inverse seeded with `seed` (what the control path's IK does
  /// when it tracks a path: the wrist representation nearest the seed, the redundancy split by the
  /// shares around it, the micro yaw's limit passing the rest to the base turntable). Within the
  /// solver's wrist band (needle vertical, IsurPuncturingSolver::kWristBand) the yaw q4 + q5 stays
  /// the seed's and the roll q8 turns instead: a vertical goal is reached without turning the arm
  /// about the vertical, and a step at the lock does not jump the yaw.
  Reachability inverseNear(std::span<const KDL::Frame> tools_in_base, std::span<const double> seed,
                           std::span<double> q) override;
  /// Of the two representations of the wrist angles (pitch θ and π - θ), the one nearest `start`
  /// (joints q4..q8) whose joints follow the start's redundancy rule without any clamping (q4
  /// where the yaw share leaves it, q6 - q7 the start's): the goal of a path that does not turn
  /// the base turntable. When that one is on the other pitch branch than the start's
  /// (IsurPuncturingSolver::branch) or there is none, the solver's answer on the start's branch
  /// (the elbow at the nearest split the delta reaches, as the controllers take it) when nearer;
  /// else inverseNear(). (The solver alone picks the representation nearest over all joints,
  /// which may need the turntable where a half turn of the roll q8 would do.)
  Reachability inverseGoal(std::span<const KDL::Frame> tools_in_base, std::span<const double> start,
                           std::span<double> q) override;
  /// Where inverseGoal chose between the rule's goal on the other pitch branch and the solver's
  /// on the start's: the one it did not choose. Otherwise Unreachable.
  Reachability inverseGoalAlternative(std::span<const KDL::Frame> tools_in_base, std::span<const double> start,
                                      std::span<double> q) override;
  /// Seven coordinates [q1, q2, q3 (m), q4, q5, pitch = q6 + q7, roll = q8 (rad)], the redundancy
  /// resolved as the IK of the control path resolves it: with the geometry's base_angle, c[3] is
  /// that angle and the yaw c[3] + c[4] splits between q4 and q5 by the solver's rule; with its
  /// pitch_difference, q6 - q7 is that (NaN: the shares from the start). The base turntable q4 stays between its
  /// start and goal angles.
  std::size_t coordinateCount() const override { return 7; }
  /// The segment's pitch q6 + q7 passing ±90°: `before` and `after` are the configuration at the
  /// crossing with the pitch kCrossingMargin before and after it, yaw, roll and sliders equal, so
  /// that the needle turns through the vertical in one plane. A segment with one end at the
  /// vertical (within the wrist band) and the other not: that end is `before` (or `after`) itself
  /// and the other is it with the pitch kCrossingMargin towards the far end, so the needle leaves
  /// (or reaches) the vertical in that end's yaw plane.
  bool singularCrossing(std::span<const double> a, std::span<const double> b, std::span<double> before,
                        std::span<double> after) const override;
  static constexpr double kCrossingMargin = 0.02;  // rad
  /// Width of coordinate 3's bounds when the geometry's base_angle fixes the base (rad; OMPL wants
  /// lower < upper; jointsOf uses only the yaw c[3] + c[4]).
  static constexpr double kBaseCoordinateWidth = 1e-9;
  void coordinateScales(std::span<double> scale) const override;
  void coordinateBounds(std::span<const double> start, std::span<const double> goal, std::span<double> lower,
                        std::span<double> upper) const override;
  void jointsOf(std::span<const double> c, std::span<const double> start, std::span<double> q) const override;
  void coordinatesOf(std::span<const double> q, std::span<double> c) const override;

 private:
  /// Joints for the ZYX wrist angles (yaw, pitch, roll) of `target` split by the shares around
  /// `seed` without clamping; false when a joint leaves its limits or the delta cannot place the
  /// platform.
  bool onRule(const KDL::Frame& target, double yaw, double pitch, double roll, std::span<const double> seed,
              std::span<double> q);
  /// inverseGoal for a vertical needle (within the solver's wrist band): the start's yaw, unless the
  /// roll then lies within kRollMargin of a limit.
  Reachability verticalGoal(std::span<const KDL::Frame> tools_in_base, std::span<const double> start,
                            std::span<double> q);
  /// inverseGoal's goal in `preferred` and, when it chose between two, the other in `alternative`.
  Reachability goalChoices(std::span<const KDL::Frame> tools_in_base, std::span<const double> start,
                           std::span<double> preferred, std::span<double> alternative, bool& has_alternative);
  static constexpr double kRollMargin = 0.2;  // rad

  kinematics::IsurPuncturingSolver solver_;
  WarmStart<1> warm_;
  KDL::JntArray q_;
  KDL::JntArray seed_;
  std::array<double, kinematics::IsurPuncturingSolver::kJoints> preferred_{}, alternative_{};  // goalChoices' scratch
};

/// Two-armed I-SUR (14 DOF), one solver for both tools: tool 0 = Endo Stitch (4-DOF arm), tool 1
/// = gripper (6-DOF arm). Links: kinematics::IsurSuturingSolver::linkFrames (12).
///
/// Joint space: the 14 joints of the solver; velocity limits those of the simulated robot
/// (SimulatedISURSuturingRobot: 0.1 m/s sliders, 1.5 rad/s revolute). The macro + Endo Stitch
/// sub-structure (q1..q8) is planned exactly as IsurPuncturingModel plans the puncturing robot
/// (its seven redundancy-resolved coordinates, its goal rule, its crossings of the vertical
/// Endo Stitch through the singular pose itself); the 6-DOF arm's joints q9..q14 are coordinates
/// themselves, bounded to the start's elbow and wrist branch (kinematics::Puma260Solver::branch:
/// the planner never searches across the arm's elbow or wrist singularity, which the control
/// path's IK refuses to cross). inverseNear is the split IK on the seed's branch
/// (IsurSuturingSolver::inverseOnBranch: what kinematics::ContinuousIsurSuturingIk solves), so a
/// verified path is one the robot follows without a branch change.
class IsurSuturingModel final : public RobotModel {
 public:
  /// Default warm-start seed: sliders at 0.1 m, the 6-DOF arm at (0, 0.5, -0.5, 0, 0.5, 0) rad.
  static KDL::JntArray defaultSeed();

  explicit IsurSuturingModel(const kinematics::IsurSuturingGeometry& geometry = kinematics::IsurSuturingGeometry{},
                             const KDL::JntArray& seed = defaultSeed());

  std::size_t toolCount() const override { return 2; }
  std::size_t linkCount() const override { return kinematics::IsurSuturingSolver::kLinks; }
  Reachability solve(std::span<const KDL::Frame> tools_in_base, std::span<KDL::Frame> links_in_base) override;
  /// Back to the seed given at construction or by the last setSeed().
  void resetWarmStart() override { warm_.reset(); }

  /// Next solve() (and every one after resetWarmStart()) starts from `q` (14 joints, m and rad).
  /// @throws std::invalid_argument otherwise.
  void setSeed(const KDL::JntArray& q) { warm_.setSeed(q); }
  const KDL::JntArray& joints() const { return warm_.joints(); }
  kinematics::IsurSuturingSolver& solver() { return solver_; }

  static constexpr std::size_t kRightJoints = kinematics::IsurSuturingSolver::kRightJoints;
  static constexpr std::size_t kLeftJoints = kinematics::IsurSuturingSolver::kLeftJoints;
  /// Coordinates of the macro + Endo Stitch sub-structure (IsurPuncturingModel's).
  static constexpr std::size_t kRightCoordinates = 7;
  /// How far inside the 6-DOF arm's elbow and wrist singularities its coordinate bounds stay (rad):
  /// near them the Cartesian path needs large joint speeds.
  static constexpr double kBranchBoundMargin = 0.02;
  std::size_t jointCount() const override { return kinematics::IsurSuturingSolver::kJoints; }
  void jointLimits(std::span<double> lower, std::span<double> upper, std::span<double> max_velocity) const override;
  bool linkFramesAt(std::span<const double> q, std::span<KDL::Frame> links_in_base) override;
  /// Tool 0: link 5 (the Endo Stitch tip); tool 1: link 11 (the gripper).
  std::size_t toolLink(std::size_t tool) const override { return tool == 0 ? 5 : 11; }
  void seedJoints(std::span<double> q) const override;
  /// The split IK on the branch of `seed` (both sub-structures), nearest it; OtherBranch when only
  /// another branch reaches the tools.
  Reachability inverseNear(std::span<const KDL::Frame> tools_in_base, std::span<const double> seed,
                           std::span<double> q) override;
  /// The Endo Stitch sub-structure by IsurPuncturingModel::inverseGoal (its redundancy rule from
  /// the start), then the 6-DOF arm from that platform on the start's branch, nearest the start.
  Reachability inverseGoal(std::span<const KDL::Frame> tools_in_base, std::span<const double> start,
                           std::span<double> q) override;
  /// The Endo Stitch sub-structure by IsurPuncturingModel::inverseGoalAlternative, then the 6-DOF
  /// arm as inverseGoal places it; Unreachable when the sub-structure has no alternative.
  Reachability inverseGoalAlternative(std::span<const KDL::Frame> tools_in_base, std::span<const double> start,
                                      std::span<double> q) override;
  /// IsurPuncturingModel::singularCrossing of q1..q8; the 6-DOF arm's joints on the segment at the
  /// same fraction as the pitch q6 + q7 of each of the two configurations.
  bool singularCrossing(std::span<const double> a, std::span<const double> b, std::span<double> before,
                        std::span<double> after) const override;
  /// 13 coordinates: IsurPuncturingModel's 7 of q1..q8, then q9..q14 (rad).
  std::size_t coordinateCount() const override { return kRightCoordinates + kLeftJoints; }
  void coordinateScales(std::span<double> scale) const override;
  /// q1..q8's as IsurPuncturingModel's; q9..q14 within their limits and, for the elbow q11 and the
  /// wrist q13, within the start's branch (kBranchBoundMargin inside its singular boundaries).
  void coordinateBounds(std::span<const double> start, std::span<const double> goal, std::span<double> lower,
                        std::span<double> upper) const override;
  void jointsOf(std::span<const double> c, std::span<const double> start, std::span<double> q) const override;
  void coordinatesOf(std::span<const double> q, std::span<double> c) const override;

 private:
  /// `right`: how the Endo Stitch sub-structure's goal joints (in seed_, q1..q8) were reached; when
  /// Reachable, the 6-DOF arm from that platform on the start's branch, nearest the start, and all
  /// 14 joints into `q`.
  Reachability withGripperArm(Reachability right, std::span<const KDL::Frame> tools_in_base,
                              std::span<const double> start, std::span<double> q);
  Reachability reachability(kinematics::IkStatus status) const;

  kinematics::IsurSuturingSolver solver_;
  IsurPuncturingModel right_;  // the macro + Endo Stitch sub-structure's planning rules
  kinematics::Puma260Parameters left_parameters_;
  WarmStart<2> warm_;
  KDL::JntArray q_;
  KDL::JntArray seed_;
};

/// The real robot models for the robots of `scene`, by name: `ur5` → Ur5Model; `isur` with one
/// tool → IsurPuncturingModel, with two → IsurSuturingModel (default geometries and seeds).
/// @throws std::invalid_argument naming a robot of another name and the accepted names.
RobotModels makeRobotModels(const SceneDescription& scene);

}  // namespace cobra::planning
