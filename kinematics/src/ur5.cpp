#include "cobra/kinematics/ur5.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "checks.hpp"

namespace cobra::kinematics {

namespace {

constexpr double kPi = std::numbers::pi;
/// |sin θ5| below this is the wrist singularity: θ6 is then taken from the seed.
constexpr double kWristSingular = 1e-10;
/// Branch angles closer than this (rad) are the same solution (e.g. elbow straight: θ3 = ±0).
constexpr double kSameBranch = 1e-12;

}  // namespace

std::vector<DhRow> urDhRows(const Ur5Parameters& p, const JointLimits& limits) {
  std::vector<DhRow> rows = {{.a = 0.0, .alpha = kPi / 2, .d = p.d1},  {.a = p.a2, .alpha = 0.0, .d = 0.0},
                             {.a = p.a3, .alpha = 0.0, .d = 0.0},      {.a = 0.0, .alpha = kPi / 2, .d = p.d4},
                             {.a = 0.0, .alpha = -kPi / 2, .d = p.d5}, {.a = 0.0, .alpha = 0.0, .d = p.d6}};
  for (std::size_t i = 0; i < rows.size() && i < limits.size(); ++i) {
    rows[i].lower = limits.lower[i];
    rows[i].upper = limits.upper[i];
  }
  return rows;
}

JointLimits Ur5Solver::defaultLimits() { return revoluteLimits(6, -2.0 * kPi, 2.0 * kPi); }

namespace {

const Ur5Parameters& checked(const Ur5Parameters& p, const JointLimits& limits) {
  detail::requireFinite("UR5", "d1", p.d1, "m");
  detail::requireNonZero("UR5", "a2", p.a2, "m");
  detail::requireNonZero("UR5", "a3", p.a3, "m");
  detail::requireFinite("UR5", "d4", p.d4, "m");
  detail::requireFinite("UR5", "d5", p.d5, "m");
  detail::requireNonZero("UR5", "d6", p.d6, "m");
  detail::requireRevolute("UR5", limits, 6);
  return p;
}

}  // namespace

Ur5Solver::Ur5Solver(const Ur5Parameters& parameters, const JointLimits& limits, const KDL::Frame& base,
                     const KDL::Frame& tool)
    : DhAnalyticSolver(SerialChainModel("UR5", urDhRows(checked(parameters, limits), limits), base, tool)),
      parameters_(parameters) {}

// Derivation (frames i of the DH table; n1 = z1 = (sin θ1, -cos θ1, 0) is the normal of the arm
// plane, in which the axes 2, 3, 4 are parallel to n1):
//  θ1: the wrist point p5 = p6 - d6·z6 lies d4 off the arm plane: p5·n1 = d4, i.e.
//      r sin(θ1 - φ) = d4 with p5 = r (cos φ, sin φ): two shoulder solutions.
//  θ5, θ6: n1 seen from the flange frame is (s5 c6, -s5 s6, c5): c5 = n1·z6, |s5| = |(n1·x6, n1·y6)|
//      (two wrist solutions ±), then θ6 from n1·x6 and n1·y6.
//  θ2, θ3, θ4: T14 = A1⁻¹ T A6⁻¹ A5⁻¹ is a planar 3R arm (a2, a3, then α4 = π/2): the origin of
//      frame 3 is that of frame 4 minus d4 along z1; law of cosines for θ3, then θ2; θ2+θ3+θ4 is
//      the angle of x4 in the plane.
IkStatus Ur5Solver::allInverse(const KDL::Frame& target, const KDL::JntArray& seed, IkSolutionSet& solutions) noexcept {
  solutions.reset(6);
  if (!validFrame(target) || !validJointArray(seed, 6)) return IkStatus::BadInput;
  const Ur5Parameters& p = parameters_;
  const std::vector<DhRow>& rows = model().rows();
  const KDL::Frame t = lastDhFrame(target);  // flange in DH frame 0
  const KDL::Vector x6 = t.M.UnitX();
  const KDL::Vector y6 = t.M.UnitY();
  const KDL::Vector z6 = t.M.UnitZ();
  const KDL::Vector p5 = t.p - p.d6 * z6;

  const double r = std::hypot(p5.x(), p5.y());
  if (r < std::abs(p.d4) * (1.0 - 1e-12) || r == 0.0) return IkStatus::Unreachable;
  const double phi = std::atan2(p5.y(), p5.x());
  const double shoulder = std::asin(std::min(1.0, p.d4 / r));
  const std::array<double, 2> theta1 = {phi + shoulder, phi + kPi - shoulder};
  const int shoulder_count = std::abs(kPi - 2.0 * shoulder) < kSameBranch ? 1 : 2;

  std::array<double, 6> q{};
  for (int i1 = 0; i1 < shoulder_count; ++i1) {
    const double s1 = std::sin(theta1[i1]);
    const double c1 = std::cos(theta1[i1]);
    // n1 seen from the flange: (s5 c6, -s5 s6, c5). atan2 keeps θ5 accurate near the singularity,
    // where acos of the position formula (p·n1 = d4 + d6 c5) would lose half the digits.
    const double n1_x6 = x6.x() * s1 - x6.y() * c1;
    const double n1_y6 = y6.x() * s1 - y6.y() * c1;
    const double c5 = z6.x() * s1 - z6.y() * c1;
    const double abs_s5 = std::hypot(n1_x6, n1_y6);
    const int wrist_count = abs_s5 < kWristSingular ? 1 : 2;
    for (int i5 = 0; i5 < wrist_count; ++i5) {
      const double s5 = i5 == 0 ? abs_s5 : -abs_s5;
      const double theta5 = std::atan2(s5, c5);
      const double theta6 = abs_s5 < kWristSingular ? seed(5) : std::atan2(-n1_y6 / s5, n1_x6 / s5);
      const KDL::Frame t14 = dhTransform(rows[0], theta1[i1]).Inverse() * t * dhTransform(rows[5], theta6).Inverse() *
                             dhTransform(rows[4], theta5).Inverse();
      const double px = t14.p.x();
      const double py = t14.p.y();
      double elbow = 0.0;
      if (!detail::clampedAcos((px * px + py * py - p.a2 * p.a2 - p.a3 * p.a3) / (2.0 * p.a2 * p.a3), elbow)) continue;
      const int elbow_count = elbow < kSameBranch || kPi - elbow < kSameBranch ? 1 : 2;
      for (int i3 = 0; i3 < elbow_count; ++i3) {
        const double theta3 = i3 == 0 ? elbow : -elbow;
        const double theta2 = std::atan2(py, px) - std::atan2(p.a3 * std::sin(theta3), p.a2 + p.a3 * std::cos(theta3));
        const double theta234 = std::atan2(t14.M(1, 0), t14.M(0, 0));
        q = {theta1[i1], theta2, theta3, theta234 - theta2 - theta3, theta5, theta6};
        for (double& value : q) value = wrapToPi(value);
        solutions.push(q);
      }
    }
  }
  return solutions.empty() ? IkStatus::Unreachable : IkStatus::Ok;
}

std::unique_ptr<KinematicsSolver> makeUr5Solver(SolverKind kind, const Ur5Parameters& parameters,
                                                const JointLimits& limits, const KDL::Frame& base,
                                                const KDL::Frame& tool) {
  auto closed_form = std::make_unique<Ur5Solver>(parameters, limits, base, tool);
  const SerialChainModel& model = closed_form->model();
  return chooseSolver(kind, std::move(closed_form), model);
}

}  // namespace cobra::kinematics
