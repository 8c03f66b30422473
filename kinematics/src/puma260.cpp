#include "cobra/kinematics/puma260.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

#include "checks.hpp"

namespace cobra::kinematics {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
/// |sin θ5| below this is the wrist singularity: θ4 is then taken from the seed.
constexpr double kWristSingular = 1e-10;
/// Branch angles closer than this (rad) are the same solution.
constexpr double kSameBranch = 1e-12;
const Puma260Parameters& checked(const Puma260Parameters& p, const JointLimits& limits, std::string_view name) {
  const std::string robot(name);
  detail::requireFinite(robot, "d1", p.d1, "m");
  detail::requireNonZero(robot, "a2", p.a2, "m");
  detail::requireFinite(robot, "a3", p.a3, "m");
  detail::requireFinite(robot, "d3", p.d3, "m");
  detail::requireFinite(robot, "d4", p.d4, "m");
  detail::requireFinite(robot, "d6", p.d6, "m");
  if (p.a3 == 0.0 && p.d4 == 0.0)
    throw std::invalid_argument(robot + ": parameters a3 and d4 are both 0 m: the forearm has no length");
  detail::requireRevolute(robot, limits, 6);
  return p;
}

}  // namespace

Puma260Parameters Puma260Parameters::puma560() {
  return Puma260Parameters{.d1 = 0.0, .a2 = 0.4318, .a3 = 0.0203, .d3 = 0.15005, .d4 = 0.4318, .d6 = 0.0};
}

std::vector<DhRow> pumaDhRows(const Puma260Parameters& p, const JointLimits& limits) {
  std::vector<DhRow> rows = {{.a = 0.0, .alpha = kPi / 2, .d = p.d1},   {.a = p.a2, .alpha = 0.0, .d = 0.0},
                             {.a = p.a3, .alpha = -kPi / 2, .d = p.d3}, {.a = 0.0, .alpha = kPi / 2, .d = p.d4},
                             {.a = 0.0, .alpha = -kPi / 2, .d = 0.0},   {.a = 0.0, .alpha = 0.0, .d = p.d6}};
  for (std::size_t i = 0; i < rows.size() && i < limits.size(); ++i) {
    rows[i].lower = limits.lower[i];
    rows[i].upper = limits.upper[i];
  }
  return rows;
}

JointLimits Puma260Solver::defaultLimits() {
  JointLimits limits = revoluteLimits(6, 0.0, 0.0);
  limits.lower = {-160 * kDeg, -45 * kDeg, -225 * kDeg, -110 * kDeg, -100 * kDeg, -266 * kDeg};
  limits.upper = {160 * kDeg, 225 * kDeg, 45 * kDeg, 170 * kDeg, 100 * kDeg, 266 * kDeg};
  return limits;
}

Puma260Solver::Puma260Solver(const Puma260Parameters& parameters, const JointLimits& limits, const KDL::Frame& base,
                             const KDL::Frame& tool, std::string_view name)
    : DhAnalyticSolver(
          SerialChainModel(std::string(name), pumaDhRows(checked(parameters, limits, name), limits), base, tool)),
      parameters_(parameters),
      elbow_offset_(std::atan2(parameters.d4, parameters.a3)) {}

// Derivation (n1 = z1 = (sin θ1, -cos θ1, 0), the normal of the arm plane; axes 2 and 3 are
// parallel to n1; the wrist centre w = p6 - d6·z6 is the common origin of frames 4, 5, 6):
//  θ1: w lies d3 off the arm plane: (w - d1 z0)·n1 = d3, i.e. r sin(θ1 - φ) = d3 (two shoulders).
//  θ3: in frame 1, (x, y) of w = Rz(θ2)·(a2 + a3 c3 - d4 s3, a3 s3 + d4 c3), so
//      x² + y² = a2² + a3² + d4² + 2 a2 (a3 c3 - d4 s3): ρ cos(θ3 + β) = K with ρ = |(a3, d4)|,
//      β = atan2(d4, a3) (two elbows).
//  θ2: the angle of (x, y) minus the angle of the rotated vector.
//  θ4, θ5, θ6: R36 = R03ᵀ R = Rz(θ4)·Ry(-θ5)·Rz(θ6): third column (-c4 s5, -s4 s5, c5), third row
//      (s5 c6, -s5 s6, c5) (two wrists, ±s5).
IkStatus Puma260Solver::allInverse(const KDL::Frame& target, const KDL::JntArray& seed,
                                   IkSolutionSet& solutions) noexcept {
  solutions.reset(6);
  if (!validFrame(target) || !validJointArray(seed, 6)) return IkStatus::BadInput;
  const Puma260Parameters& p = parameters_;
  const std::vector<DhRow>& rows = model().rows();
  const KDL::Frame t = lastDhFrame(target);  // flange in DH frame 0
  const KDL::Vector wrist = t.p - p.d6 * t.M.UnitZ();

  const double r = std::hypot(wrist.x(), wrist.y());
  if (r < std::abs(p.d3) * (1.0 - 1e-12) || r == 0.0) return IkStatus::Unreachable;
  const double phi = std::atan2(wrist.y(), wrist.x());
  const double shoulder = std::asin(std::clamp(p.d3 / r, -1.0, 1.0));
  const std::array<double, 2> theta1 = {phi + shoulder, phi + kPi - shoulder};
  const int shoulder_count = std::abs(kPi - 2.0 * shoulder) < kSameBranch ? 1 : 2;
  const double rho = std::hypot(p.a3, p.d4);
  const double beta = std::atan2(p.d4, p.a3);

  std::array<double, 6> q{};
  for (int i1 = 0; i1 < shoulder_count; ++i1) {
    const KDL::Vector w1 = dhTransform(rows[0], theta1[i1]).Inverse() * wrist;  // wrist centre in frame 1
    IkBranch shoulder_branch;
    detail::chooseBranch(shoulder_branch, detail::kShoulderBit, w1.x());
    const double k = (w1.x() * w1.x() + w1.y() * w1.y() - p.a2 * p.a2 - p.a3 * p.a3 - p.d4 * p.d4) / (2.0 * p.a2);
    double elbow = 0.0;
    if (!detail::clampedAcos(k / rho, elbow)) continue;
    const int elbow_count = elbow < kSameBranch || kPi - elbow < kSameBranch ? 1 : 2;
    for (int i3 = 0; i3 < elbow_count; ++i3) {
      const double theta3 = (i3 == 0 ? elbow : -elbow) - beta;
      IkBranch elbow_branch = shoulder_branch;
      detail::chooseBranch(elbow_branch, detail::kElbowBit, std::sin(theta3 + beta));
      const double s3 = std::sin(theta3);
      const double c3 = std::cos(theta3);
      const double theta2 =
          std::atan2(w1.y(), w1.x()) - std::atan2(p.a3 * s3 + p.d4 * c3, p.a2 + p.a3 * c3 - p.d4 * s3);
      const KDL::Rotation r03 =
          (dhTransform(rows[0], theta1[i1]) * dhTransform(rows[1], theta2) * dhTransform(rows[2], theta3)).M;
      const KDL::Rotation r36 = r03.Inverse() * t.M;
      const double c5 = r36(2, 2);
      const double abs_s5 = std::hypot(r36(0, 2), r36(1, 2));
      const int wrist_count = abs_s5 < kWristSingular ? 1 : 2;
      for (int i5 = 0; i5 < wrist_count; ++i5) {
        const double s5 = i5 == 0 ? abs_s5 : -abs_s5;
        const double theta5 = std::atan2(s5, c5);
        double theta4 = seed(3);
        double theta6 = 0.0;
        if (abs_s5 >= kWristSingular) {
          theta4 = std::atan2(-r36(1, 2) / s5, -r36(0, 2) / s5);
          theta6 = std::atan2(-r36(2, 1) / s5, r36(2, 0) / s5);
        } else {
          // Axes 4 and 6 aligned: Ry(θ5)·Rz(-θ4)·R36 = Rz(θ6).
          const KDL::Rotation rest = KDL::Rotation::RotY(theta5) * KDL::Rotation::RotZ(-theta4) * r36;
          theta6 = std::atan2(rest(1, 0), rest(0, 0));
        }
        q = {theta1[i1], theta2, theta3, theta4, theta5, theta6};
        for (double& value : q) value = wrapToPi(value);
        IkBranch branch = elbow_branch;
        detail::chooseBranch(branch, detail::kWristBit, s5);
        solutions.push(q, branch);
      }
    }
  }
  return solutions.empty() ? IkStatus::Unreachable : IkStatus::Ok;
}

IkBranch Puma260Solver::branch(std::span<const double> q) const noexcept {
  IkBranch branch;
  if (q.size() != 6) return branch;
  const Puma260Parameters& p = parameters_;
  // The wrist centre's coordinate along x1 (see the derivation above): Rz(θ2) applied to
  // (a2 + a3 c3 - d4 s3, a3 s3 + d4 c3).
  const double s3 = std::sin(q[2]);
  const double c3 = std::cos(q[2]);
  const double u = p.a2 + p.a3 * c3 - p.d4 * s3;
  const double v = p.a3 * s3 + p.d4 * c3;
  detail::chooseBranch(branch, detail::kShoulderBit, std::cos(q[1]) * u - std::sin(q[1]) * v);
  detail::chooseBranch(branch, detail::kElbowBit, std::sin(q[2] + elbow_offset_));
  detail::chooseBranch(branch, detail::kWristBit, std::sin(q[4]));
  return branch;
}

std::unique_ptr<KinematicsSolver> makePuma260Solver(SolverKind kind, const Puma260Parameters& parameters,
                                                    const JointLimits& limits) {
  auto closed_form = std::make_unique<Puma260Solver>(parameters, limits);
  const SerialChainModel& model = closed_form->model();
  return chooseSolver(kind, std::move(closed_form), model);
}

}  // namespace cobra::kinematics
