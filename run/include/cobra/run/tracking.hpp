#pragma once
/// @file
/// "The robot did what it was told" (the procedure's fidelity), per tracked tool: the error between
/// the commanded tool pose (what is written to the robot's desired-pose input, e.g. the variable
/// admittance's output, so the intended compliance in contact is not an error) and the measured
/// one, and an independent check of joint jumps. The runner feeds one TrackingMonitor per entry of
/// the application's `run.tracking` (run/README.md) every step; nothing here knows an application.

#include <limits>
#include <string>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>


namespace cobra::run {

/// The procedure acceptance: the worst tracking error of a robot in autonomous motions [mm, deg].
constexpr double kAcceptedTrackingMm = 2.0;
constexpr double kAcceptedTrackingDeg = 1.0;

/// The worst of one quantity over a run: its value, when and in which task state.
struct Worst {
  double value = 0.0;
  double at = 0.0;    ///< s
  std::string state;  ///< the robot's chart state then ("" when none)
};

/// Tracking figures of one robot over the samples that count (TrackingMonitor::step).
struct TrackingFigures {
  std::string robot;               ///< the entry's name, e.g. "I-SUR needle"
  Worst position_mm;               ///< mm, |commanded - measured| tool point
  Worst orientation_deg;           ///< deg, angle of commanded^-1 · measured
  double seconds_above_5mm = 0.0;  ///< s of samples with a position error above 5 mm
  double seconds_sampled = 0.0;    ///< s of samples that counted (autonomous)
  /// Independent branch-change check: episodes of a measured joint moving at >= kSaturated of its
  /// velocity limit (a servo chasing a jump in its command), or beyond it (a jump).
  int joint_jumps = 0;
  Worst joint_speed;  ///< worst measured joint speed as a fraction of its limit (1 = at the limit)
  std::string joint_jump_log;  ///< "t s joint i (state)" of the first episodes, one per line
  /// Largest jump of the commanded position between two consecutive samples, counted or not [m]
  /// (a switch between deployments must not make the command jump), and when [s].
  double max_command_step = 0.0;
  double max_command_step_at = 0.0;
};

/// Follows one robot's commanded and measured poses. Not real-time: the runner's bookkeeping.
class TrackingMonitor {
 public:
  /// Fraction of a joint's velocity limit from which a measured step counts as a jump episode.
  static constexpr double kSaturated = 0.95;
  /// Below this fraction an episode is over.
  static constexpr double kCalm = 0.5;

  /// @param max_velocity per joint [rad/s or m/s] (the robot's velocity limits); empty: no joint check.
  /// @param period the step [s] (1 ms).
  TrackingMonitor(std::string robot, std::vector<double> max_velocity, double period);

  /// Wall clock: a sample's joints may be up to `seconds` older than the sample (published by the
  /// robot's thread before), so a joint's change between two samples may span that much more
  /// time; the joint check divides by it too. 0 (default, the lockstep clock): exact samples.
  void setSampleSkew(double seconds) { skew_ = seconds; }

  /// One step at time `t` [s]. Only samples with `counts` (an autonomous motion of this robot)
  /// enter the figures; `joints` (measured, may be nullptr) feed the joint check, their speed
  /// taken over the time since the last sample when it is longer than the period (a late sample
  /// on the wall clock), else over the period, plus the sample skew.
  void step(double t, bool counts, const std::string& state, const KDL::Frame& commanded, const KDL::Frame& measured,
            const KDL::JntArray* joints);
  /// The largest position [mm] and orientation [deg] errors since the last call (counted or not),
  /// for the plots; NaN when no sample came. Resets them.
  std::pair<double, double> takeWindowMaximum();
  /// The last sample's errors [mm, deg] (NaN before the first).
  double lastMm() const { return last_mm_; }
  double lastDeg() const { return last_deg_; }
  const TrackingFigures& figures() const { return figures_; }

 private:
  TrackingFigures figures_;
  std::vector<double> max_velocity_;
  double period_;
  KDL::JntArray previous_joints_;
  double previous_joints_t_ = 0.0;  // s, when previous_joints_ was sampled
  double last_sample_t_ = 0.0;      // s, the last step's t
  bool have_sample_t_ = false;
  double skew_ = 0.0;               // s, see setSampleSkew
  KDL::Frame previous_command_;
  bool have_command_ = false;
  bool have_joints_ = false;
  bool in_episode_ = false;
  double window_mm_ = std::numeric_limits<double>::quiet_NaN();
  double window_deg_ = std::numeric_limits<double>::quiet_NaN();
  double last_mm_ = std::numeric_limits<double>::quiet_NaN();
  double last_deg_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace cobra::run
