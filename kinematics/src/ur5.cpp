#include "cobra/kinematics/ur5.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
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
      parameters_(parameters),
      identity_base_(base == KDL::Frame::Identity()),
      identity_tool_(tool == KDL::Frame::Identity()) {}

// The DH product A1 ... A6 with A_i = Rz(θi)·Tz(di)·Tx(ai)·Rx(αi), regrouped: R01 = Rz(θ1)·Rx(π/2);
// joints 2-4 turn about the arm plane's normal z1, so in frame 1 the wrist frame 4 is at
// p4 = (a2 c2 + a3 c23, a2 s2 + a3 s23, d4) with R14 = Rz(θ234)·Rx(π/2); Rx(π/2)·Rz(θ5)·Rx(-π/2) is
// Ry(-θ5), so R16 = Rz(θ234)·Ry(-θ5)·Rz(θ6), z4 = Rz(θ234)·(0, -1, 0) and z5 = R16·(0, 0, 1).
// Six sines and cosines and about 100 multiplications instead of eight frame products.
IkStatus Ur5Solver::forward(const KDL::JntArray& q, KDL::Frame& pose) noexcept {
  if (!validJointArray(q, 6)) return IkStatus::BadInput;
  const Ur5Parameters& p = parameters_;
  // Plain doubles (KDL::JntArray's operator() is an out-of-line call), so that each cos/sin pair
  // of one angle becomes one sincos call.
  const double* j = q.data.data();
  const double q23 = j[1] + j[2], q234 = q23 + j[3];
  const double c1 = std::cos(j[0]), s1 = std::sin(j[0]);
  const double c2 = std::cos(j[1]), s2 = std::sin(j[1]);
  const double c23 = std::cos(q23), s23 = std::sin(q23);
  const double c234 = std::cos(q234), s234 = std::sin(q234);
  const double c5 = std::cos(j[4]), s5 = std::sin(j[4]);
  const double c6 = std::cos(j[5]), s6 = std::sin(j[5]);
  // R16 = Rz(θ234) · [c5 c6, -c5 s6, -s5; s6, c6, 0; s5 c6, -s5 s6, c5].
  const double a00 = c5 * c6, a01 = -c5 * s6, a02 = -s5;
  const double b00 = c234 * a00 - s234 * s6, b01 = c234 * a01 - s234 * c6, b02 = c234 * a02;
  const double b10 = s234 * a00 + c234 * s6, b11 = s234 * a01 + c234 * c6, b12 = s234 * a02;
  const double b20 = s5 * c6, b21 = -s5 * s6, b22 = c5;
  // Flange origin in frame 1: p4 + d5 z4 + d6 z5.
  const double x = p.a2 * c2 + p.a3 * c23 + p.d5 * s234 + p.d6 * b02;
  const double y = p.a2 * s2 + p.a3 * s23 - p.d5 * c234 + p.d6 * b12;
  const double z = p.d4 + p.d6 * b22;
  // Frame 1 in frame 0: R01 = [c1, 0, s1; s1, 0, -c1; 0, 1, 0], origin (0, 0, d1).
  KDL::Frame flange(KDL::Rotation(c1 * b00 + s1 * b20, c1 * b01 + s1 * b21, c1 * b02 + s1 * b22,  //
                                  s1 * b00 - c1 * b20, s1 * b01 - c1 * b21, s1 * b02 - c1 * b22,  //
                                  b10, b11, b12),
                    KDL::Vector(c1 * x + s1 * z, s1 * x - c1 * z, p.d1 + y));
  if (!identity_base_) flange = frameProduct(model().base(), flange);
  pose = identity_tool_ ? flange : frameProduct(flange, model().tool());
  return IkStatus::Ok;
}

namespace {

/// `angle` (|angle| < 5π, as the sums of atan2 results below) wrapped into (-π, π] without the
/// libm call of wrapToPi: the closed form runs at every control step.
double wrapSmall(double angle) noexcept {
  while (angle > kPi) angle -= 2.0 * kPi;
  while (angle <= -kPi) angle += 2.0 * kPi;
  return angle;
}

}  // namespace

// Derivation (frames i of the DH table; n1 = z1 = (sin θ1, -cos θ1, 0) is the normal of the arm
// plane, in which the axes 2, 3, 4 are parallel to n1; x1 = (cos θ1, sin θ1, 0), y1 = z0):
//  θ1: the wrist point p5 = p6 - d6·z6 lies d4 off the arm plane: p5·n1 = d4, i.e.
//      r sin(θ1 - φ) = d4 with p5 = r (cos φ, sin φ): two shoulder solutions, with p5·x1 =
//      ±r cos(asin(d4 / r)) (+ for the first: the shoulder branch bit is the sign of p5·x1).
//  θ5, θ6: n1 seen from the flange frame is (s5 c6, -s5 s6, c5): c5 = n1·z6, |s5| = |(n1·x6, n1·y6)|
//      (two wrist solutions ±), then c6 = n1·x6 / s5, s6 = -n1·y6 / s5.
//  θ2, θ3, θ4: frames 1 -> 4 are a planar 3R arm (a2, a3, then α4 = π/2). With R04 = R06·Rz(-θ6)·
//      Rx(π/2)·Rz(-θ5): z4 = -s6 x6 - c6 y6, x4 = c5 c6 x6 - c5 s6 y6 - s5 z6, and the origin of
//      frame 4 is p4 = p5 - d5 z4. In frame 1, p4 = (a2 c2 + a3 c23, a2 s2 + a3 s23, d4): the law
//      of cosines gives θ3, then θ2; θ2+θ3+θ4 is the angle of x4 in the plane (x1, y1).
// Everything is computed from the sines and cosines the geometry already gives (no DH products,
// one atan2 per angle): the eight solutions cost about as much as KDL's forward kinematics.
IkStatus Ur5Solver::allInverse(const KDL::Frame& target, const KDL::JntArray& seed, IkSolutionSet& solutions) noexcept {
  return solve(target, seed, IkBranch::any(), solutions);
}

IkStatus Ur5Solver::inverseOnBranch(const KDL::Frame& target, const KDL::JntArray& seed, IkBranch branch,
                                    KDL::JntArray& q_out) noexcept {
  if (q_out.rows() != jointCount()) return IkStatus::BadInput;
  // The solutions on `branch` alone first (one shoulder, wrist and elbow when the branch is not
  // ambiguous: a quarter of the work, and the selection among one). The nearest of them fitting
  // the limits is the nearest on the branch among all eight, so it is the answer; when none
  // fits, all eight tell whether another branch would have (Discontinuous) or not (JointLimits).
  if (solve(target, seed, branch, on_branch_) == IkStatus::Ok &&
      selectNearest(on_branch_, limits(), seed, q_out, branch) == IkStatus::Ok)
    return IkStatus::Ok;
  return AnalyticSolver::inverseOnBranch(target, seed, branch, q_out);
}

namespace {

/// True when the choices `decided` (branch bits) made so far in `partial` are compatible with
/// `keep` (IkBranch::compatibleWith restricted to those bits).
bool keeps(IkBranch keep, IkBranch partial, std::uint8_t decided) noexcept {
  return ((keep.bits ^ partial.bits) & decided & ~(keep.ambiguous | partial.ambiguous)) == 0;
}

}  // namespace

IkStatus Ur5Solver::solve(const KDL::Frame& target, const KDL::JntArray& seed, IkBranch keep,
                          IkSolutionSet& solutions) const noexcept {
  solutions.reset(6);
  if (!validFrame(target) || !validJointArray(seed, 6)) return IkStatus::BadInput;
  const Ur5Parameters& p = parameters_;
  const KDL::Frame t = lastDhFrame(target);  // flange in DH frame 0
  const KDL::Vector x6 = t.M.UnitX();
  const KDL::Vector y6 = t.M.UnitY();
  const KDL::Vector z6 = t.M.UnitZ();
  const KDL::Vector p5 = t.p - p.d6 * z6;

  const double r = std::sqrt(p5.x() * p5.x() + p5.y() * p5.y());
  if (r < std::abs(p.d4) * (1.0 - 1e-12) || r == 0.0) return IkStatus::Unreachable;
  const double phi = std::atan2(p5.y(), p5.x());
  const double sin_shoulder = std::min(1.0, p.d4 / r);
  const double shoulder = std::asin(sin_shoulder);
  const double cos_shoulder = std::sqrt(std::max(0.0, 1.0 - sin_shoulder * sin_shoulder));
  const double cos_phi = p5.x() / r;
  const double sin_phi = p5.y() / r;
  const int shoulder_count = std::abs(kPi - 2.0 * shoulder) < kSameBranch ? 1 : 2;
  const double a2a3 = 2.0 * p.a2 * p.a3;
  const double a_squares = p.a2 * p.a2 + p.a3 * p.a3;

  std::array<double, 6> q{};
  for (int i1 = 0; i1 < shoulder_count; ++i1) {
    // θ1 = φ + shoulder, or φ + π - shoulder.
    const double theta1 = i1 == 0 ? phi + shoulder : phi + kPi - shoulder;
    const double s1 = i1 == 0 ? sin_phi * cos_shoulder + cos_phi * sin_shoulder
                              : -(sin_phi * cos_shoulder - cos_phi * sin_shoulder);
    const double c1 = i1 == 0 ? cos_phi * cos_shoulder - sin_phi * sin_shoulder
                              : -(cos_phi * cos_shoulder + sin_phi * sin_shoulder);
    IkBranch shoulder_branch;
    detail::chooseBranch(shoulder_branch, detail::kShoulderBit, (i1 == 0 ? 1.0 : -1.0) * r * cos_shoulder);
    if (!keeps(keep, shoulder_branch, detail::kShoulderBit)) continue;
    // n1 seen from the flange: (s5 c6, -s5 s6, c5). atan2 keeps θ5 accurate near the singularity,
    // where acos of the position formula (p·n1 = d4 + d6 c5) would lose half the digits.
    const double n1_x6 = x6.x() * s1 - x6.y() * c1;
    const double n1_y6 = y6.x() * s1 - y6.y() * c1;
    const double n1_z6 = z6.x() * s1 - z6.y() * c1;
    const double abs_s5 = std::sqrt(n1_x6 * n1_x6 + n1_y6 * n1_y6);
    const double unit = std::sqrt(abs_s5 * abs_s5 + n1_z6 * n1_z6);  // 1 up to the target's rounding
    const bool singular = abs_s5 < kWristSingular;
    // The second wrist (s5 -> -s5) negates c6, s6 and x4: θ5 -> -θ5, θ6 and θ234 turn by π. One
    // atan2 per pair (atan2 is most of the cost of this function).
    const double c5 = n1_z6 / unit;
    const double theta5_up = std::atan2(abs_s5 / unit, c5);
    double c6_up = 0.0;
    double s6_up = 0.0;
    double theta6_up = seed.data(5);
    if (singular) {
      s6_up = std::sin(theta6_up);
      c6_up = std::cos(theta6_up);
    } else {
      c6_up = n1_x6 / abs_s5;
      s6_up = -n1_y6 / abs_s5;
      theta6_up = std::atan2(s6_up, c6_up);
    }
    const KDL::Vector x4_up = c5 * c6_up * x6 - c5 * s6_up * y6 - (abs_s5 / unit) * z6;
    const double theta234_up = std::atan2(x4_up.z(), x4_up.x() * c1 + x4_up.y() * s1);
    const int wrist_count = singular ? 1 : 2;
    for (int i5 = 0; i5 < wrist_count; ++i5) {
      const double sign = i5 == 0 ? 1.0 : -1.0;
      const double s5 = sign * abs_s5 / unit;
      const double theta5 = sign * theta5_up;
      const double c6 = sign * c6_up;
      const double s6 = sign * s6_up;
      const double theta6 = i5 == 0 ? theta6_up : theta6_up + kPi;
      const double theta234 = i5 == 0 ? theta234_up : theta234_up + kPi;
      IkBranch wrist_branch = shoulder_branch;
      detail::chooseBranch(wrist_branch, detail::kWristBit, s5);
      if (!keeps(keep, wrist_branch, detail::kShoulderBit | detail::kWristBit)) continue;
      const KDL::Vector z4 = -s6 * x6 - c6 * y6;
      const KDL::Vector p4 = p5 - p.d5 * z4;
      // p4 in frame 1 (origin (0, 0, d1), axes x1, y1 = z0).
      const double px = p4.x() * c1 + p4.y() * s1;
      const double py = p4.z() - p.d1;
      const double cos3 = (px * px + py * py - a_squares) / a2a3;
      double elbow = 0.0;
      if (!detail::clampedAcos(cos3, elbow)) continue;
      const double c3 = std::clamp(cos3, -1.0, 1.0);
      const double abs_s3 = std::sqrt(std::max(0.0, 1.0 - c3 * c3));
      const double planar = std::atan2(py, px);
      // θ2 = planar - atan2(a3 s3, a2 + a3 c3); the second elbow (s3 -> -s3) negates the atan2.
      const double elbow_angle = std::atan2(p.a3 * abs_s3, p.a2 + p.a3 * c3);
      const int elbow_count = elbow < kSameBranch || kPi - elbow < kSameBranch ? 1 : 2;
      for (int i3 = 0; i3 < elbow_count; ++i3) {
        const double theta3 = i3 == 0 ? elbow : -elbow;
        const double theta2 = i3 == 0 ? planar - elbow_angle : planar + elbow_angle;
        IkBranch branch = wrist_branch;
        detail::chooseBranch(branch, detail::kElbowBit, i3 == 0 ? abs_s3 : -abs_s3);
        if (!keep.compatibleWith(branch)) continue;
        q = {wrapSmall(theta1), wrapSmall(theta2), theta3, wrapSmall(theta234 - theta2 - theta3), theta5,
             wrapSmall(theta6)};
        solutions.push(q, branch);
      }
    }
  }
  return solutions.empty() ? IkStatus::Unreachable : IkStatus::Ok;
}

IkBranch Ur5Solver::branch(std::span<const double> q) const noexcept {
  IkBranch branch;
  if (q.size() != 6) return branch;
  const Ur5Parameters& p = parameters_;
  // The wrist point's component along x1 (the shoulder bit, see the derivation above):
  // p5 in frame 1 = (a2 c2 + a3 c23 + d5 s234, ...).
  const double lateral = p.a2 * std::cos(q[1]) + p.a3 * std::cos(q[1] + q[2]) + p.d5 * std::sin(q[1] + q[2] + q[3]);
  detail::chooseBranch(branch, detail::kShoulderBit, lateral);
  detail::chooseBranch(branch, detail::kElbowBit, std::sin(q[2]));
  detail::chooseBranch(branch, detail::kWristBit, std::sin(q[4]));
  return branch;
}

std::unique_ptr<KinematicsSolver> makeUr5Solver(SolverKind kind, const Ur5Parameters& parameters,
                                                const JointLimits& limits, const KDL::Frame& base,
                                                const KDL::Frame& tool) {
  auto closed_form = std::make_unique<Ur5Solver>(parameters, limits, base, tool);
  const SerialChainModel& model = closed_form->model();
  return chooseSolver(kind, std::move(closed_form), model);
}

}  // namespace cobra::kinematics
