#pragma once
/// @file
/// Closed-form kinematics of the Unimation Puma 260 (thesis ch. 6: the retrofitted Puma whose
/// Kinematics Solver component exists in a KDL and a closed-form version, interchangeable, §6.2.4).
///
/// DH table (standard DH, Rz(θ)·Tz(d)·Tx(a)·Rx(α)), in the Paul & Shimano convention for the Puma
/// family (R. Paul, B. Shimano, G. Mayer, "Kinematic control equations for simple manipulators",
/// IEEE Trans. SMC 11(6), 1981) as written by P. Corke's Robotics Toolbox `mdl_puma560`:
///
/// | joint | a (m)  | d (m)   | α (rad) | Puma 260 value and source                                 |
/// |-------|--------|---------|---------|-----------------------------------------------------------|
/// | 1     | 0      | d1      | π/2     | d1 = 0.3302 (13.0 in, base plate to shoulder axis)        |
/// | 2     | a2     | 0       | 0       | a2 = 0.2032 (8.0 in, upper arm)                           |
/// | 3     | a3     | d3      | -π/2    | a3 = 0 (no elbow offset on the 260), d3 = 0.12623         |
/// | 4     | 0      | d4      | π/2     | d4 = 0.2032 (8.0 in, forearm)                             |
/// | 5     | 0      | 0       | -π/2    |                                                           |
/// | 6     | 0      | d6      | 0       | d6 = 0.05537 (wrist centre to flange)                     |
///
/// What was used and why: the thesis (§6.1.1) gives no dimensions of the Puma 260. The 8.0 in
/// upper arm and forearm and the 13.0 in shoulder height are Unimation's Puma 250/260 link lengths
/// as listed in university course material on the Puma 260 (link lengths a = 13.0, c = 8.0,
/// e = 8.0 in; shoulder offsets b + d ≈ 5 in; flange f ≈ 2.5 in). The shoulder offset 0.12623 m and
/// wrist-to-flange 0.05537 m are the values of a public OROCOS/KDL model of the Puma 260 (a KDL
/// chain with DH(0.2032, 0, 0, 0), DH(0, -π/2, -0.12623, 0), DH(0, π/2, 0.2032, 0), ...), i.e.
/// measured values within 1 % of the course sheet's 5 in and within 8 mm of its 2.5 in. Replace
/// them by the calibration of the actual robot (Puma260Parameters) when it is known.
/// Default joint limits: the Puma 560's ranges in this same DH convention (Corke's `mdl_puma560`
/// qlim), since no Puma 260 ranges in this convention were found; they are a parameter.

#include <memory>
#include <string_view>

#include "cobra/kinematics/kinematics_solver.hpp"
#include "cobra/kinematics/serial_chain.hpp"

namespace cobra::kinematics {

/// Lengths of a Puma-type arm (m). Defaults: Puma 260 (see the file comment).
struct Puma260Parameters {
  double d1 = 0.3302;   ///< base plate to shoulder axis, m
  double a2 = 0.2032;   ///< upper arm (shoulder to elbow axis), m
  double a3 = 0.0;      ///< elbow offset along the forearm's normal, m (Puma 560: 0.0203)
  double d3 = 0.12623;  ///< shoulder offset (lateral), m
  double d4 = 0.2032;   ///< forearm (elbow axis to wrist centre), m
  double d6 = 0.05537;  ///< wrist centre to flange, m

  /// The Puma 560 of Corke's `mdl_puma560` (d1 = 0): a2 0.4318, a3 0.0203, d3 0.15005, d4 0.4318.
  static Puma260Parameters puma560();
};

/// The DH rows of a Puma-type arm, limits from `limits` (6 revolute joints, rad).
std::vector<DhRow> pumaDhRows(const Puma260Parameters& parameters, const JointLimits& limits);

/// Closed-form Puma solver (Paul & Shimano's decomposition: shoulder left/right from the wrist
/// centre's lateral offset, elbow up/down from the law of cosines, spherical wrist flip/no-flip
/// from the ZYZ-like wrist rotation). No allocation on the real-time calls.
class Puma260Solver final : public DhAnalyticSolver {
 public:
  /// [-160, 160], [-45, 225], [-225, 45], [-110, 170], [-100, 100], [-266, 266] degrees, in rad.
  static JointLimits defaultLimits();

  /// @param name the robot's name in messages (another Puma-type arm, e.g. an I-SUR micro arm)
  /// @throws std::invalid_argument naming the parameter or joint ("Puma 260: parameter a2 is 0 m:
  /// ...", "Puma 260: joint 2 limits ...") when a length is not finite, a2 is 0, a3 and d4 are
  /// both 0, or the limits are invalid.
  explicit Puma260Solver(const Puma260Parameters& parameters = Puma260Parameters{},
                         const JointLimits& limits = defaultLimits(), const KDL::Frame& base = KDL::Frame::Identity(),
                         const KDL::Frame& tool = KDL::Frame::Identity(), std::string_view name = "Puma 260");

  const Puma260Parameters& parameters() const noexcept { return parameters_; }

  /// Up to 8 solutions (2 shoulder × 2 elbow × 2 wrist); at the wrist singularity (θ5 = 0 or π,
  /// axes 4 and 6 aligned) θ4 takes the seed's value.
  /// Each solution is labelled with its branch (see `branch`).
  IkStatus allInverse(const KDL::Frame& target, const KDL::JntArray& seed, IkSolutionSet& solutions) noexcept override;
  using AnalyticSolver::inverse;

  /// Branch bits: 0 shoulder (set when the wrist centre lies behind the base axis along x1 =
  /// (cos q1, sin q1, 0)), 1 elbow (sin(q3 + atan2(d4, a3)) < 0: the two law-of-cosines
  /// solutions), 2 wrist (sin q5 < 0: flip). Each is ambiguous within kBranchMargin of 0 (wrist
  /// centre on the base axis, stretched elbow, axes 4 and 6 aligned).
  IkBranch branch(std::span<const double> q) const noexcept override;

 private:
  Puma260Parameters parameters_;
  double elbow_offset_;  ///< atan2(d4, a3), rad
};

/// The Puma 260 solver of `kind`, all on the same DH table, limits, base and tool.
std::unique_ptr<KinematicsSolver> makePuma260Solver(SolverKind kind,
                                                    const Puma260Parameters& parameters = Puma260Parameters{},
                                                    const JointLimits& limits = Puma260Solver::defaultLimits());

}  // namespace cobra::kinematics
