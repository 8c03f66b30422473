#pragma once
/// @file
/// Closed-form kinematics of the Universal Robots UR5 (thesis §4.3.2: the arm holding the
/// ultrasound probe in the puncturing setup): all (up to 8) inverse solutions and the one nearest
/// to a seed.
///
/// DH table (standard DH, Rz(θ)·Tz(d)·Tx(a)·Rx(α)), UR5 column of Universal Robots' "DH parameters
/// for calculations of kinematics and dynamics", https://www.universal-robots.com/articles/ur/
/// application-installation/dh-parameters-for-calculations-of-kinematics-and-dynamics/ :
///
/// | joint | a (m)    | d (m)    | α (rad) | θ offset |
/// |-------|----------|----------|---------|----------|
/// | 1     | 0        | 0.089159 | π/2     | 0        |
/// | 2     | -0.425   | 0        | 0       | 0        |
/// | 3     | -0.39225 | 0        | 0       | 0        |
/// | 4     | 0        | 0.10915  | π/2     | 0        |
/// | 5     | 0        | 0.09465  | -π/2    | 0        |
/// | 6     | 0        | 0.0823   | 0       | 0        |
///
/// Joint ranges ±360° on all joints (thesis §4.3.2 table), so every joint value has two
/// representatives in the limits; `inverse` picks the one nearest to the seed.
/// The inverse follows the standard geometric derivation for this family (shoulder offset d4,
/// wrist offsets d5, d6, three parallel axes 2–4), cf. K. P. Hawkins, "Analytic Inverse Kinematics
/// for the Universal Robots UR-5/UR-10 Arms", Georgia Tech, 2013; the derivation is repeated in
/// ur5.cpp.

#include <memory>
#include <string_view>

#include "cobra/kinematics/kinematics_solver.hpp"
#include "cobra/kinematics/serial_chain.hpp"

namespace cobra::kinematics {

/// The six non-zero lengths of the UR DH table (m). Defaults: UR5. (UR10: d1 0.1273, a2 -0.612,
/// a3 -0.5723, d4 0.163941, d5 0.1157, d6 0.0922.)
struct Ur5Parameters {
  double d1 = 0.089159;  ///< base to shoulder, along z0, m
  double a2 = -0.425;    ///< upper arm, m
  double a3 = -0.39225;  ///< forearm, m
  double d4 = 0.10915;   ///< shoulder offset (lateral), m
  double d5 = 0.09465;   ///< wrist 1 to wrist 2, m
  double d6 = 0.0823;    ///< wrist 2 to flange, m
};

/// The DH rows of a UR arm with `parameters`, limits from `limits` (6 joints, rad).
std::vector<DhRow> urDhRows(const Ur5Parameters& parameters, const JointLimits& limits);

/// Closed-form UR5 solver. Model: the DH table above plus base and tool frames; FK is the product
/// of the DH transforms, computed in closed form (three parallel axes: one rotation about the
/// arm plane's normal by θ2+θ3+θ4). `forward`, `allInverse` and `inverse` are noexcept and allocate
/// nothing.
class Ur5Solver final : public DhAnalyticSolver {
 public:
  /// Limits of the real arm: ±2π rad on every joint.
  static JointLimits defaultLimits();

  /// @param base pose of the UR base frame in the world (m)
  /// @param tool pose of the tool (e.g. probe tip) in the flange frame (m)
  /// @throws std::invalid_argument naming the parameter or joint ("UR5: parameter a2 is nan: ...",
  /// "UR5: joint 3 limits [2, 1] rad: min must be <= max") when a length is not finite, a2 or a3
  /// is zero or d6 is zero (the closed form divides by them), or the limits are invalid.
  explicit Ur5Solver(const Ur5Parameters& parameters = Ur5Parameters{}, const JointLimits& limits = defaultLimits(),
                     const KDL::Frame& base = KDL::Frame::Identity(), const KDL::Frame& tool = KDL::Frame::Identity());

  const Ur5Parameters& parameters() const noexcept { return parameters_; }

  /// The DH chain's product (model().forward) in closed form: equal within rounding (below 1e-12 m and
  /// rad, tested against the chain and KDL on seeded random joints). BadInput for a wrong-size or non-finite q.
  IkStatus forward(const KDL::JntArray& q, KDL::Frame& pose) noexcept override;

  /// Up to 8 solutions: shoulder left/right (θ1) × wrist up/down (θ5) × elbow up/down (θ3);
  /// duplicates at the boundaries of these branches are dropped. At the wrist singularity
  /// (sin θ5 = 0, axes 4 and 6 aligned) θ6 takes the seed's value. BadInput for a non-finite or
  /// non-orthonormal target or a wrong-size seed.
  /// Each solution is labelled with its branch (see `branch`).
  IkStatus allInverse(const KDL::Frame& target, const KDL::JntArray& seed, IkSolutionSet& solutions) noexcept override;
  using AnalyticSolver::inverse;

  /// Branch bits: 0 shoulder (set when the wrist point p5 lies behind the base axis as seen along
  /// x1 = (cos q1, sin q1, 0): its lateral coordinate a2 c2 + a3 c23 + d5 s234 < 0), 1 elbow (sin q3
  /// < 0), 2 wrist (sin q5 < 0). Each is ambiguous within kBranchMargin of 0: the shoulder
  /// singularity (p5 on the base axis), the stretched or folded elbow, the wrist singularity
  /// (axes 4 and 6 aligned).
  IkBranch branch(std::span<const double> q) const noexcept override;
  /// As AnalyticSolver::inverseOnBranch (the same answer), solving the branch's solutions first
  /// and all eight only when none of those fits the limits (to tell Discontinuous from
  /// JointLimits). No allocation.
  IkStatus inverseOnBranch(const KDL::Frame& target, const KDL::JntArray& seed, IkBranch branch,
                           KDL::JntArray& q_out) noexcept override;

 private:
  /// allInverse restricted to the solutions compatible with `keep` (IkBranch::any(): all).
  IkStatus solve(const KDL::Frame& target, const KDL::JntArray& seed, IkBranch keep,
                 IkSolutionSet& solutions) const noexcept;

  Ur5Parameters parameters_;
  IkSolutionSet on_branch_;  // inverseOnBranch's workspace
  bool identity_base_ = false;  // forward skips the product with an identity base / tool
  bool identity_tool_ = false;
};

/// The UR5 solver of `kind`, all on the same DH table, limits, base and tool.
std::unique_ptr<KinematicsSolver> makeUr5Solver(SolverKind kind, const Ur5Parameters& parameters = Ur5Parameters{},
                                                const JointLimits& limits = Ur5Solver::defaultLimits(),
                                                const KDL::Frame& base = KDL::Frame::Identity(),
                                                const KDL::Frame& tool = KDL::Frame::Identity());

}  // namespace cobra::kinematics
