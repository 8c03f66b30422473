#include "cobra/kinematics/serial_chain.hpp"

#include <dlfcn.h>

#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <kdl/chainiksolverpos_nr_jl.hpp>
#include <kdl/chainiksolvervel_pinv.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include "cobra/kinematics/frame_product.hpp"
#include "cobra/kinematics/geometry.hpp"

namespace cobra::kinematics {

namespace {

constexpr std::size_t kMaxDhRows = 32;

void checkFinite(const std::string& robot, std::size_t joint, const char* parameter, double value, const char* unit) {
  if (std::isfinite(value)) return;
  throw std::invalid_argument(robot + ": joint " + std::to_string(joint + 1) + " DH parameter " + parameter + " is " +
                              formatNumber(value) + ": give a finite value in " + unit);
}

void checkFiniteFrame(const std::string& robot, const char* which, const KDL::Frame& frame) {
  if (validFrame(frame)) return;
  throw std::invalid_argument(robot + ": the " + std::string(which) +
                              " frame is not a pose: its translation must be finite and its rotation orthonormal");
}

}  // namespace

KDL::Frame SerialChainModel::link(std::size_t i, double q) const noexcept {
  // KDL::Frame::DH's formula with the row's cos α and sin α computed once: the same bits.
  const DhRow& row = rows_[i];
  const double theta = row.type == JointType::Revolute ? row.theta + q : row.theta;
  const double d = row.type == JointType::Revolute ? row.d : row.d + q;
  const double ct = std::cos(theta), st = std::sin(theta);
  const double ca = alpha_trig_[i][0], sa = alpha_trig_[i][1];
  return KDL::Frame(KDL::Rotation(ct, -st * ca, st * sa, st, ct * ca, -ct * sa, 0, sa, ca),
                    KDL::Vector(row.a * ct, row.a * st, d));
}

KDL::Frame dhTransform(const DhRow& row, double q) noexcept {
  if (row.type == JointType::Revolute) return KDL::Frame::DH(row.a, row.alpha, row.d, row.theta + q);
  return KDL::Frame::DH(row.a, row.alpha, row.d + q, row.theta);
}

SerialChainModel::SerialChainModel(std::string name, std::vector<DhRow> rows, const KDL::Frame& base,
                                   const KDL::Frame& tool)
    : name_(std::move(name)), rows_(std::move(rows)), base_(base), tool_(tool) {
  if (rows_.empty()) throw std::invalid_argument(name_ + ": the DH table is empty: give one row per joint");
  if (rows_.size() > kMaxDhRows)
    throw std::invalid_argument(name_ + ": the DH table has " + std::to_string(rows_.size()) + " rows; at most " +
                                std::to_string(kMaxDhRows) + " joints are supported");
  checkFiniteFrame(name_, "base", base_);
  checkFiniteFrame(name_, "tool", tool_);
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    const DhRow& row = rows_[i];
    checkFinite(name_, i, "a", row.a, "m");
    checkFinite(name_, i, "alpha", row.alpha, "rad");
    checkFinite(name_, i, "d", row.d, "m");
    checkFinite(name_, i, "theta", row.theta, "rad");
    limits_.types.push_back(row.type);
    limits_.lower.push_back(row.lower);
    limits_.upper.push_back(row.upper);
    alpha_trig_.push_back({std::cos(row.alpha), std::sin(row.alpha)});
  }
  validateLimits(name_, limits_, rows_.size());

  chain_.addSegment(KDL::Segment("base", KDL::Joint(KDL::Joint::Fixed), base_));
  // Reach bound: |base offset| + Σ (|a| + |d| + |prismatic travel|) + |tool offset|.
  reach_bound_ = norm(tool_.p);
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    const DhRow& row = rows_[i];
    const auto type = row.type == JointType::Revolute ? KDL::Joint::RotZ : KDL::Joint::TransZ;
    chain_.addSegment(KDL::Segment("link" + std::to_string(i + 1), KDL::Joint("joint" + std::to_string(i + 1), type),
                                   KDL::Frame::DH(row.a, row.alpha, row.d, row.theta)));
    reach_bound_ += std::abs(row.a) + std::abs(row.d);
    if (row.type == JointType::Prismatic) reach_bound_ += std::max(std::abs(row.lower), std::abs(row.upper));
  }
  chain_.addSegment(KDL::Segment("tool", KDL::Joint(KDL::Joint::Fixed), tool_));
}

KDL::Frame SerialChainModel::forward(std::span<const double> q) const noexcept {
  KDL::Frame pose = base_;
  for (std::size_t i = 0; i < rows_.size() && i < q.size(); ++i) pose = frameProduct(pose, link(i, q[i]));
  return frameProduct(pose, tool_);
}

bool SerialChainModel::linkFrames(std::span<const double> q, std::span<KDL::Frame> frames) const noexcept {
  if (q.size() != rows_.size() || frames.size() != linkCount()) return false;
  frames[0] = base_;
  for (std::size_t i = 0; i < rows_.size(); ++i) frames[i + 1] = frameProduct(frames[i], link(i, q[i]));
  frames[rows_.size() + 1] = frameProduct(frames[rows_.size()], tool_);
  return true;
}

std::string kdlLmaConflict() {
  // KDL's ChainIkSolverPos_LMA::CartToJnt locates liborocos-kdl; the Eigen functions it calls out of
  // line (JacobiSVD<MatrixXd> constructor, allocate, destructor) must resolve into the same library.
  constexpr const char* kLmaSolve = "_ZN3KDL20ChainIkSolverPos_LMA9CartToJntERKNS_8JntArrayERKNS_5FrameERS1_";
  constexpr const char* kEigenCalls[] = {
      "_ZN5Eigen9JacobiSVDINS_6MatrixIdLin1ELin1ELi0ELin1ELin1EEELi2EEC1Ellj",
      "_ZN5Eigen9JacobiSVDINS_6MatrixIdLin1ELin1ELi0ELin1ELin1EEELi2EE8allocateEllj",
      "_ZN5Eigen9JacobiSVDINS_6MatrixIdLin1ELin1ELi0ELin1ELin1EEELi2EED1Ev",
  };
  Dl_info kdl{};
  void* const solve = dlsym(RTLD_DEFAULT, kLmaSolve);
  if (solve == nullptr || dladdr(solve, &kdl) == 0) return "";  // KDL's LMA is not loaded (or not exported)
  for (const char* symbol : kEigenCalls) {
    Dl_info bound{};
    void* const target = dlsym(RTLD_DEFAULT, symbol);
    if (target == nullptr || dladdr(target, &bound) == 0 || bound.dli_fbase == kdl.dli_fbase) continue;
    return std::string("KDL's Levenberg-Marquardt solver (") + kdl.dli_fname + ") cannot run in this process: its " +
           "Eigen::JacobiSVD calls bind to the copy in " + bound.dli_fname +
           ", built against another Eigen version with another member layout (Debian 12's OMPL 1.5 uses Eigen 3.3, "
           "KDL 1.5.1 Eigen 3.4), and the first solve would abort the process in Eigen's SVD assertion";
  }
  return "";
}

struct SerialChainSolver::Workspace {
  explicit Workspace(const SerialChainModel& model, const IterativeIkOptions& options)
      : fk(model.chain()),
        jac(model.chain()),
        ik_velocity(model.chain()),
        q_min(model.jointCount()),
        q_max(model.jointCount()),
        q_work(model.jointCount()),
        jacobian(model.jointCount()) {
    for (unsigned i = 0; i < model.jointCount(); ++i) {
      q_min(i) = model.limits().lower[i];
      q_max(i) = model.limits().upper[i];
    }
    // KDL's own stopping thresholds are set far below cobra's tolerances, which are checked on
    // the result; NR_JL compares each twist component, LMA the weighted squared error.
    constexpr double kNrTwistEps = 1e-12;
    constexpr double kLmaSquaredErrorEps = 1e-24;
    const int iterations = static_cast<int>(options.max_iterations);
    if (options.method == IterativeIk::NewtonRaphsonJL) {
      nr = std::make_unique<KDL::ChainIkSolverPos_NR_JL>(model.chain(), q_min, q_max, fk, ik_velocity,
                                                         options.max_iterations, kNrTwistEps);
    } else {
      // Equal weights on position (m) and orientation (rad): KDL's default 0.01 on rotation
      // trades orientation accuracy away, which cobra does not accept.
      Eigen::Matrix<double, 6, 1> weights = Eigen::Matrix<double, 6, 1>::Ones();
      lma = std::make_unique<KDL::ChainIkSolverPos_LMA>(model.chain(), weights, kLmaSquaredErrorEps, iterations);
    }
  }

  KDL::ChainFkSolverPos_recursive fk;
  KDL::ChainJntToJacSolver jac;
  KDL::ChainIkSolverVel_pinv ik_velocity;
  std::unique_ptr<KDL::ChainIkSolverPos_NR_JL> nr;
  std::unique_ptr<KDL::ChainIkSolverPos_LMA> lma;
  KDL::JntArray q_min;
  KDL::JntArray q_max;
  KDL::JntArray q_work;
  KDL::Jacobian jacobian;
};

namespace {

/// Gauss–Newton steps q += Jᵀ(JJᵀ + λ²I)⁻¹ e with an exact pose residual e, after KDL's solver:
/// KDL measures rotation residuals with Rotation::GetRotAngle, which rounds angles below 1e-6 rad
/// to zero, so NR_JL and LMA stop with orientation errors of 1e-8 to 1e-6 rad. Only started when
/// KDL's answer is already within `kPolishRadius` of the target; no allocation (6×6 fixed-size).
void polish(KDL::ChainFkSolverPos_recursive& fk, KDL::ChainJntToJacSolver& jac_solver, const KDL::Frame& target,
            const IterativeIkOptions& options, KDL::JntArray& q, KDL::Jacobian& jacobian) noexcept {
  constexpr int kMaxSteps = 4;
  constexpr double kPolishRadius = 1e-3;  // m and rad
  constexpr double kDampingSquared = 1e-16;
  const unsigned n = q.rows();
  for (int step = 0; step < kMaxSteps; ++step) {
    KDL::Frame reached;
    fk.JntToCart(q, reached);
    const KDL::Vector e_p = target.p - reached.p;
    const KDL::Vector e_r = rotationVector(target.M * reached.M.Inverse());
    if (norm(e_p) > kPolishRadius || norm(e_r) > kPolishRadius) return;
    if (norm(e_p) <= 0.1 * options.position_tolerance && norm(e_r) <= 0.1 * options.orientation_tolerance) return;
    jac_solver.JntToJac(q, jacobian);
    Vector6d e;
    e << e_p.x(), e_p.y(), e_p.z(), e_r.x(), e_r.y(), e_r.z();
    Matrix6d jjt = kDampingSquared * Matrix6d::Identity();
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c)
        for (unsigned j = 0; j < n; ++j)
          jjt(r, c) += jacobian(static_cast<unsigned>(r), j) * jacobian(static_cast<unsigned>(c), j);
    const Vector6d y = jjt.ldlt().solve(e);
    for (unsigned j = 0; j < n; ++j) {
      double dq = 0.0;
      for (int r = 0; r < 6; ++r) dq += jacobian(static_cast<unsigned>(r), j) * y(r);
      q(j) += dq;
    }
  }
}

}  // namespace

SerialChainSolver::SerialChainSolver(SerialChainModel model, IterativeIkOptions options)
    : model_(std::make_unique<const SerialChainModel>(std::move(model))), options_(options) {
  if (!(options_.position_tolerance > 0.0) || !(options_.orientation_tolerance > 0.0))
    throw std::invalid_argument(model_->name() + ": IK tolerances must be > 0 (position " +
                                formatNumber(options_.position_tolerance) + " m, orientation " +
                                formatNumber(options_.orientation_tolerance) + " rad)");
  if (options_.max_iterations == 0) throw std::invalid_argument(model_->name() + ": IK max_iterations must be >= 1");
  if (options_.method == IterativeIk::LevenbergMarquardt) {
    if (const std::string conflict = kdlLmaConflict(); !conflict.empty())
      throw std::invalid_argument(model_->name() + ": " + conflict + "; use KDL's Newton-Raphson solver (kdl_nr) or "
                                  "the closed form");
  }
  work_ = std::make_unique<Workspace>(*model_, options_);
}

SerialChainSolver::~SerialChainSolver() = default;
SerialChainSolver::SerialChainSolver(SerialChainSolver&&) noexcept = default;
SerialChainSolver& SerialChainSolver::operator=(SerialChainSolver&&) noexcept = default;

IkStatus SerialChainSolver::forward(const KDL::JntArray& q, KDL::Frame& pose) noexcept {
  if (!validJointArray(q, jointCount())) return IkStatus::BadInput;
  if (work_->fk.JntToCart(q, pose) < 0) return IkStatus::BadInput;
  return IkStatus::Ok;
}

IkStatus SerialChainSolver::jacobian(const KDL::JntArray& q, KDL::Jacobian& jacobian) noexcept {
  if (!validJointArray(q, jointCount()) || jacobian.columns() != jointCount()) return IkStatus::BadInput;
  if (work_->jac.JntToJac(q, jacobian) < 0) return IkStatus::BadInput;
  return IkStatus::Ok;
}

IkStatus SerialChainSolver::inverse(const KDL::Frame& target, const KDL::JntArray& seed,
                                    KDL::JntArray& q_out) noexcept {
  if (!validJointArray(seed, jointCount()) || q_out.rows() != jointCount() || !validFrame(target))
    return IkStatus::BadInput;
  if (norm(target.p - model_->base().p) > model_->reachBound()) return IkStatus::Unreachable;
  KDL::JntArray& q = work_->q_work;
  // KDL's return codes are not trusted alone (NR_JL reports success from its own twist threshold,
  // LMA stops on small increments): the answer is judged by its forward kinematics below.
  if (options_.method == IterativeIk::NewtonRaphsonJL) {
    work_->nr->CartToJnt(seed, target, q);
  } else {
    work_->lma->CartToJnt(seed, target, q);
  }
  for (unsigned i = 0; i < jointCount(); ++i) {
    if (!std::isfinite(q(i))) return IkStatus::NoConvergence;
  }
  polish(work_->fk, work_->jac, target, options_, q, work_->jacobian);
  KDL::Frame reached;
  work_->fk.JntToCart(q, reached);
  if (norm(reached.p - target.p) > options_.position_tolerance ||
      orientationError(reached.M, target.M) > options_.orientation_tolerance)
    return IkStatus::NoConvergence;
  const std::span<double> values(q.data.data(), jointCount());
  if (!wrapIntoLimits(values, limits(), std::span<const double>(seed.data.data(), jointCount())))
    return IkStatus::JointLimits;
  q_out.data = q.data;
  return IkStatus::Ok;
}

int SerialChainSolver::lastIterations() const noexcept { return work_->lma ? work_->lma->lastNrOfIter : 0; }

IkStatus DhAnalyticSolver::forward(const KDL::JntArray& q, KDL::Frame& pose) noexcept {
  if (!validJointArray(q, jointCount())) return IkStatus::BadInput;
  pose = model_.forward(std::span<const double>(q.data.data(), q.rows()));
  return IkStatus::Ok;
}

std::unique_ptr<KinematicsSolver> chooseSolver(SolverKind kind, std::unique_ptr<KinematicsSolver> closed_form,
                                               const SerialChainModel& model) {
  if (kind == SolverKind::ClosedForm) return closed_form;
  const IterativeIk method =
      kind == SolverKind::KdlNewtonRaphson ? IterativeIk::NewtonRaphsonJL : IterativeIk::LevenbergMarquardt;
  return std::make_unique<SerialChainSolver>(model, IterativeIkOptions{.method = method});
}

}  // namespace cobra::kinematics
