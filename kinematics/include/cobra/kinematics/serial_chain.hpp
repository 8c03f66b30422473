#pragma once
/// @file
/// A generic serial robot from standard Denavit–Hartenberg parameters (the thesis' Kinematics
/// Solver, §6.2.4): the immutable model (`SerialChainModel`: DH table, limits, base and tool
/// frames, the KDL::Chain built from them) and a solver over KDL (`SerialChainSolver`: FK,
/// Jacobian, and IK by Newton–Raphson with joint limits or by Levenberg–Marquardt).

#include <array>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <kdl/chain.hpp>
#include <kdl/frames.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/kinematics/kinematics_solver.hpp"
#include "cobra/kinematics/types.hpp"
#include "cobra/kinematics/frame_product.hpp"

namespace KDL {
class ChainFkSolverPos_recursive;
class ChainJntToJacSolver;
class ChainIkSolverVel_pinv;
class ChainIkSolverPos_NR_JL;
class ChainIkSolverPos_LMA;
}  // namespace KDL

namespace cobra::kinematics {

/// One row of a standard (distal) DH table: the transform from frame i-1 to frame i is
/// Rz(θ + q) · Tz(d) · Tx(a) · Rx(α) for a revolute joint and Rz(θ) · Tz(d + q) · Tx(a) · Rx(α)
/// for a prismatic one — the convention of KDL::Frame::DH and of Universal Robots' tables.
struct DhRow {
  double a = 0.0;      ///< link length along x_i, m
  double alpha = 0.0;  ///< link twist about x_i, rad
  double d = 0.0;      ///< link offset along z_{i-1}, m (added to q for a prismatic joint)
  double theta = 0.0;  ///< joint angle offset about z_{i-1}, rad (added to q for a revolute joint)
  JointType type = JointType::Revolute;
  double lower = -3.141592653589793;  ///< joint limit, rad (revolute) or m (prismatic)
  double upper = 3.141592653589793;   ///< joint limit, rad (revolute) or m (prismatic)
};

/// Rz(θ+q)·Tz(d)·Tx(a)·Rx(α) (revolute) or Rz(θ)·Tz(d+q)·Tx(a)·Rx(α) (prismatic); q in rad / m.
KDL::Frame dhTransform(const DhRow& row, double q) noexcept;

/// Immutable description of a serial robot. Pose of the tool in the world:
/// base · Π_i dhTransform(row_i, q_i) · tool.
class SerialChainModel {
 public:
  /// @param name used in every error message, e.g. "UR5"
  /// @param base pose of the DH frame 0 in the robot's base (world) frame (m)
  /// @param tool pose of the tool frame in the last DH frame (m)
  /// @throws std::invalid_argument naming the robot, the joint (1-based) and the parameter when the
  /// table is empty or longer than 32 rows, a parameter is not finite, or a joint's limits are
  /// not finite or have min > max.
  SerialChainModel(std::string name, std::vector<DhRow> rows, const KDL::Frame& base = KDL::Frame::Identity(),
                   const KDL::Frame& tool = KDL::Frame::Identity());

  const std::string& name() const noexcept { return name_; }
  const std::vector<DhRow>& rows() const noexcept { return rows_; }
  unsigned jointCount() const noexcept { return static_cast<unsigned>(rows_.size()); }
  const JointLimits& limits() const noexcept { return limits_; }
  const KDL::Frame& base() const noexcept { return base_; }
  const KDL::Frame& tool() const noexcept { return tool_; }
  /// The KDL chain: a fixed segment for the base, one RotZ/TransZ segment per DH row (tip frame
  /// KDL::Frame::DH(a, α, d, θ)), and a fixed segment for the tool.
  const KDL::Chain& chain() const noexcept { return chain_; }
  /// Upper bound of the distance from the base origin to the tool origin over all joint values
  /// in limits (m): targets beyond it are Unreachable without iterating.
  double reachBound() const noexcept { return reach_bound_; }

  /// Tool pose for `q` by the product of the DH transforms (`q.size()` == jointCount()).
  /// Real-time safe.
  KDL::Frame forward(std::span<const double> q) const noexcept;

  /// Number of frames linkFrames() writes: jointCount() + 2.
  unsigned linkCount() const noexcept { return jointCount() + 2; }
  /// Every link frame for `q` in the robot's base (world) frame: [0] the DH frame 0 (= base),
  /// [i] the DH frame i after joint i (1..n), [n + 1] the tool. The last equals forward(q).
  /// Real-time safe. Returns false (frames untouched) when `q` has not jointCount() values or
  /// `frames` has not linkCount() elements.
  bool linkFrames(std::span<const double> q, std::span<KDL::Frame> frames) const noexcept;

 private:
  /// dhTransform(rows()[i], q), bit for bit, from the row's precomputed cos α and sin α.
  KDL::Frame link(std::size_t i, double q) const noexcept;

  std::string name_;
  std::vector<DhRow> rows_;
  std::vector<std::array<double, 2>> alpha_trig_;  // per row: cos α, sin α
  JointLimits limits_;
  KDL::Frame base_;
  KDL::Frame tool_;
  KDL::Chain chain_;
  double reach_bound_ = 0.0;
};

/// Which KDL position IK solver a SerialChainSolver runs.
enum class IterativeIk {
  NewtonRaphsonJL,     ///< KDL::ChainIkSolverPos_NR_JL (pseudo-inverse steps, clamped to the limits)
  LevenbergMarquardt,  ///< KDL::ChainIkSolverPos_LMA (limits applied afterwards: 2π wrap, else JointLimits)
};

struct IterativeIkOptions {
  IterativeIk method = IterativeIk::LevenbergMarquardt;
  unsigned max_iterations = 500;
  /// Accepted tool position error after the solver returns, m.
  double position_tolerance = 1e-9;
  /// Accepted tool orientation error (angle of the residual rotation), rad.
  double orientation_tolerance = 1e-9;
};

/// Why KDL's Levenberg–Marquardt solver (KDL::ChainIkSolverPos_LMA) cannot run in this process,
/// or "" when it can. The solver keeps an Eigen::JacobiSVD<Eigen::MatrixXd> whose out-of-line
/// template functions (its constructor, allocate, destructor) liborocos-kdl exports as weak symbols,
/// and the dynamic linker binds KDL's own calls to them to the FIRST definition in the process.
/// Debian 12's libompl.so.16 (OMPL 1.5.2, built against Eigen 3.3) exports the same functions with
/// Eigen 3.3's member layout (3.4 added SVDBase::m_info before the flags), while liborocos-kdl 1.5.1
/// is built against Eigen 3.4: in a process that loads OMPL before KDL (every cobra program linking
/// the planning library, the `cobra` tool among them) the SVD is set up by OMPL's copy and read by
/// KDL's inlined code, `computeU()` reads a wrong byte, and Eigen's assertion in matrixU() (KDL is
/// built with assertions) aborts the process on the first solve. Nothing in cobra's flags can change
/// that binding (it is the system libraries' ODR violation), so the check looks at it: it names the
/// library a call of KDL's would reach when that is not liborocos-kdl itself. NR_JL is not affected
/// (KDL's own SVD_HH, no Eigen decomposition).
std::string kdlLmaConflict();

/// FK, Jacobian and iterative IK of a SerialChainModel through KDL's solvers, all constructed once
/// here. KDL's answer is finished by at most 4 Gauss–Newton steps with an exact residual (KDL rounds
/// rotation errors below 1e-6 rad to zero) and then judged by its forward kinematics.
/// `forward`, `jacobian` and `inverse` allocate nothing: KDL 1.5's NR_JL and LMA preallocate in
/// their constructors (measured with the counting operator new in serial_chain_test). Movable,
/// not copyable (KDL's solvers keep a reference to the chain).
class SerialChainSolver final : public KinematicsSolver {
 public:
  /// @throws std::invalid_argument when an option is out of range (tolerances must be > 0 and
  /// max_iterations >= 1), or when `options.method` is LevenbergMarquardt and kdlLmaConflict() says
  /// KDL's LMA cannot run in this process (the message says why and to use NewtonRaphsonJL).
  explicit SerialChainSolver(SerialChainModel model, IterativeIkOptions options = IterativeIkOptions{});
  ~SerialChainSolver() override;
  SerialChainSolver(SerialChainSolver&&) noexcept;
  SerialChainSolver& operator=(SerialChainSolver&&) noexcept;

  std::string_view name() const noexcept override { return model_->name(); }
  unsigned jointCount() const noexcept override { return model_->jointCount(); }
  const JointLimits& limits() const noexcept override { return model_->limits(); }
  const SerialChainModel& model() const noexcept { return *model_; }
  const IterativeIkOptions& options() const noexcept { return options_; }

  IkStatus forward(const KDL::JntArray& q, KDL::Frame& pose) noexcept override;
  /// Geometric Jacobian (6 × n) of the tool frame: reference point the tool origin, components in
  /// the base (world) axes; rows [v (m/s); ω (rad/s)] per unit joint velocity. `jacobian` must
  /// have n columns.
  IkStatus jacobian(const KDL::JntArray& q, KDL::Jacobian& jacobian) noexcept;
  /// Unreachable when the target is beyond reachBound(); NoConvergence when KDL stops without
  /// reaching the tolerances; JointLimits when LMA's answer has no 2π-equivalent in the limits.
  IkStatus inverse(const KDL::Frame& target, const KDL::JntArray& seed, KDL::JntArray& q_out) noexcept override;

  /// Iterations KDL's LMA solver used in the last inverse call (0 for NR_JL, which hides it).
  int lastIterations() const noexcept;

 private:
  struct Workspace;
  std::unique_ptr<const SerialChainModel> model_;
  IterativeIkOptions options_;
  std::unique_ptr<Workspace> work_;
};

/// An analytic solver of a robot described by a DH table: name, joint count, limits and FK (the
/// product of the DH transforms, no allocation) come from its SerialChainModel.
class DhAnalyticSolver : public AnalyticSolver {
 public:
  std::string_view name() const noexcept override { return model_.name(); }
  unsigned jointCount() const noexcept override { return model_.jointCount(); }
  const JointLimits& limits() const noexcept override { return model_.limits(); }
  /// The same robot as a DH chain (for KDL's solvers and cross-checks).
  const SerialChainModel& model() const noexcept { return model_; }
  IkStatus forward(const KDL::JntArray& q, KDL::Frame& pose) noexcept override;

 protected:
  explicit DhAnalyticSolver(SerialChainModel model)
      : model_(std::move(model)), base_inverse_(model_.base().Inverse()), tool_inverse_(model_.tool().Inverse()) {}
  /// `target` (tool pose in the world) as the pose of the last DH frame in DH frame 0:
  /// base⁻¹ · target · tool⁻¹.
  KDL::Frame lastDhFrame(const KDL::Frame& target) const noexcept {
    return frameProduct(frameProduct(base_inverse_, target), tool_inverse_);
  }

 private:
  SerialChainModel model_;
  KDL::Frame base_inverse_;  // inverted once: the closed forms run at every control step
  KDL::Frame tool_inverse_;
};

/// `closed_form` when `kind` is ClosedForm, otherwise a SerialChainSolver over `model` with the
/// KDL method of `kind` (the two are interchangeable behind KinematicsSolver, thesis §6.2.4).
std::unique_ptr<KinematicsSolver> chooseSolver(SolverKind kind, std::unique_ptr<KinematicsSolver> closed_form,
                                               const SerialChainModel& model);

}  // namespace cobra::kinematics
