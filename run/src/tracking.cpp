#include "cobra/run/tracking.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cobra::run {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
constexpr int kLoggedEpisodes = 10;  // joint jump episodes described in joint_jump_log

void raise(Worst& worst, double value, double t, const std::string& state) {
  if (!(value > worst.value)) return;
  worst = {value, t, state};
}

double maxOrNan(double window, double value) { return std::isnan(window) ? value : std::max(window, value); }

// The angle of the rotation Aᵀ·B [rad, 0..π] without forming it: its trace and the vector of its
// antisymmetric part are sums of products of A's and B's columns, and atan2(|v|/2, (tr - 1)/2) is
// accurate at small angles too (where acos of the trace alone loses half the digits).
double angleBetween(const KDL::Rotation& a, const KDL::Rotation& b) {
  const double* A = a.data;  // row-major: A[3 * row + column]
  const double* B = b.data;
  double trace = 0.0, sx = 0.0, sy = 0.0, sz = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double* ak = A + 3 * k;
    const double* bk = B + 3 * k;
    trace += ak[0] * bk[0] + ak[1] * bk[1] + ak[2] * bk[2];
    sx += ak[2] * bk[1] - ak[1] * bk[2];
    sy += ak[0] * bk[2] - ak[2] * bk[0];
    sz += ak[1] * bk[0] - ak[0] * bk[1];
  }
  return std::atan2(0.5 * std::sqrt(sx * sx + sy * sy + sz * sz), 0.5 * (trace - 1.0));
}

}  // namespace

TrackingMonitor::TrackingMonitor(std::string robot, std::vector<double> max_velocity, double period)
    : max_velocity_(std::move(max_velocity)), period_(period) {
  figures_.robot = std::move(robot);
}

void TrackingMonitor::step(double t, bool counts, const std::string& state, const KDL::Frame& commanded,
                           const KDL::Frame& measured, const KDL::JntArray* joints) {
  const double mm = 1000.0 * (commanded.p - measured.p).Norm();
  const double deg = kRadToDeg * angleBetween(commanded.M, measured.M);
  if (have_command_) {
    const double jump = (commanded.p - previous_command_.p).Norm();
    if (jump > figures_.max_command_step) figures_.max_command_step = jump, figures_.max_command_step_at = t;
  }
  previous_command_ = commanded;
  have_command_ = true;
  last_mm_ = mm;
  last_deg_ = deg;
  window_mm_ = maxOrNan(window_mm_, mm);
  window_deg_ = maxOrNan(window_deg_, deg);
  // s this sample stands for: the period, or on the wall clock the time since the last sample when
  // it came late (the lockstep clock samples every period exactly).
  const double weight = have_sample_t_ && t - last_sample_t_ > period_ ? t - last_sample_t_ : period_;
  have_sample_t_ = true;
  last_sample_t_ = t;
  if (counts) {
    figures_.seconds_sampled += weight;
    raise(figures_.position_mm, mm, t, state);
    raise(figures_.orientation_deg, deg, t, state);
    if (mm > 5.0) figures_.seconds_above_5mm += weight;
  }
  // rows() once: KDL::JntArray::rows is an out-of-line call.
  const unsigned n = joints == nullptr ? 0 : joints->rows();
  if (joints == nullptr || max_velocity_.empty() || n != max_velocity_.size()) {
    have_joints_ = false;
    return;
  }
  if (have_joints_ && counts) {
    // On the wall clock samples come late when the runner's thread is starved: a joint's change
    // is over the time between the samples, not one period (on the lockstep clock they are equal).
    const double interval = (t - previous_joints_t_ > 1.01 * period_ ? t - previous_joints_t_ : period_) + skew_;
    double fraction = 0.0;
    unsigned fastest = 0;
    for (unsigned i = 0; i < n; ++i) {
      const double f = std::abs(joints->data(i) - previous_joints_.data(i)) / (max_velocity_[i] * interval);
      if (f > fraction) fraction = f, fastest = i;
    }
    raise(figures_.joint_speed, fraction, t, state);
    if (!in_episode_ && fraction >= kSaturated) {
      in_episode_ = true;
      if (figures_.joint_jumps++ < kLoggedEpisodes) {
        char line[200];
        std::snprintf(line, sizeof line, "%.3f s joint %u at %.0f %% of its velocity limit (%s)\n", t, fastest + 1,
                      100.0 * fraction, state.c_str());
        figures_.joint_jump_log += line;
      }
    } else if (in_episode_ && fraction < kCalm) {
      in_episode_ = false;
    }
  } else if (!counts) {
    in_episode_ = false;
  }
  previous_joints_.data = joints->data;  // Eigen's copy: no reallocation at the same size
  previous_joints_t_ = t;
  have_joints_ = true;
}

std::pair<double, double> TrackingMonitor::takeWindowMaximum() {
  const std::pair<double, double> out{window_mm_, window_deg_};
  window_mm_ = window_deg_ = std::numeric_limits<double>::quiet_NaN();
  return out;
}

}  // namespace cobra::run
