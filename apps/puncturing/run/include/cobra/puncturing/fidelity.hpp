#pragma once
/// @file
/// "The robot did what it was told", measured during a procedure (issue 15): per robot the
/// tracking error between the commanded tool pose (what is written to the robot's desired-pose
/// input: the variable admittance's output, so the intended compliance in contact is not an
/// error) and the measured one, an independent check of joint jumps, and the clearance of the
/// measured state against the motion planner's threshold with the declared allowed contacts
/// (probe on the skin, needle in tissue) measured apart. What procedure.cpp feeds every step.

#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/planning/scene.hpp"

namespace cobra::planning {
class RobotModel;
class StateValidator;
}

namespace cobra::puncturing {

/// Issue 15's acceptance: the worst tracking error of a robot during autonomous motions [mm, deg].
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
  std::string robot;               ///< "I-SUR needle", "UR5 probe"
  Worst position_mm;               ///< mm, |commanded - measured| tool point
  Worst orientation_deg;           ///< deg, angle of commanded^-1 · measured
  double seconds_above_5mm = 0.0;  ///< s of samples with a position error above 5 mm
  double seconds_sampled = 0.0;    ///< s of samples that counted (autonomous)
  /// Independent branch-change check: episodes of a measured joint moving at >= kSaturated of its
  /// velocity limit (a servo chasing a jump in its command), or beyond it (a jump).
  int joint_jumps = 0;
  Worst joint_speed;  ///< worst measured joint speed as a fraction of its limit (1 = at the limit)
  std::string joint_jump_log;  ///< "t s joint i (state)" of the first episodes, one per line
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

  /// One step at time `t` [s]. Only samples with `counts` (an autonomous motion of this robot)
  /// enter the figures; `joints` (measured, may be nullptr) feed the joint check.
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
  bool have_joints_ = false;
  bool in_episode_ = false;
  double window_mm_ = std::numeric_limits<double>::quiet_NaN();
  double window_deg_ = std::numeric_limits<double>::quiet_NaN();
  double last_mm_ = std::numeric_limits<double>::quiet_NaN();
  double last_deg_ = std::numeric_limits<double>::quiet_NaN();
};

/// A contact the task requires between two objects of the planning scene, reported apart from
/// the clearance: "probe on skin" (us_probe / phantom, the scene's `allow`), "needle in tissue"
/// (needle / phantom, while the needle chart is between its descent to the skin and the end of
/// the extraction).
struct AllowedContact {
  std::string name;
  std::string first_object;
  std::string second_object;
};

/// One measurement of the measured state.
struct ClearanceSample {
  /// Minimum distance [m] over the planner's checked pairs, leaving out the allowed contacts in
  /// force; NaN when a measured pose is unreachable for the scene's robot models.
  double clearance = std::numeric_limits<double>::quiet_NaN();
  std::string closest;              ///< "first_object/second_object" of the clearance (when asked)
  /// (When asked) every checked pair of groups whose closest objects are at or under the
  /// threshold, "first_object/second_object" and their distance [m].
  std::vector<std::pair<std::string, double>> under_threshold;
  std::vector<double> contacts;     ///< [m] per AllowedContact, 0 when touching or inside
};

/// The planner's scene with the allowed-contact objects in groups of their own, so that their
/// distances are measured apart; distances of the measured tool poses, each robot's inverse
/// kinematics seeded with its measured joints (the collision geometry follows the real arm's
/// branch, not one the IK would pick). Not real-time.
class ClearanceMonitor {
 public:
  /// @param scene the motion planner's scene (components::buildPlanningScene of its properties).
  /// @param contacts the allowed contacts; each pair of objects is left out of the clearance
  ///                 while `measure` says it is allowed, and always measured apart. The scene's
  ///                 own `allow` pairs must be among them (they are left out of its checks).
  /// @throws std::invalid_argument naming a contact whose object the scene does not have, or a
  ///         scene `allow` pair that is not declared as a contact.
  ClearanceMonitor(planning::SceneDescription scene, std::vector<AllowedContact> contacts);
  ~ClearanceMonitor();

  /// The planner's threshold [m]: every checked pair must be farther apart.
  double threshold() const { return threshold_; }
  const std::vector<AllowedContact>& contacts() const { return contacts_; }

  /// Distances for the measured tool poses (world, m). `allowed[i]`: contact i is in force now.
  /// `joints[r]`: the measured joints of scene robot r (empty: the IK's own warm start).
  /// `name_closest`: fill ClearanceSample::closest and under_threshold (a second pass over the pairs).
  ClearanceSample measure(const KDL::Frame& needle, const KDL::Frame& probe, const std::vector<bool>& allowed,
                          const std::vector<KDL::JntArray>& joints, bool name_closest);

  /// Index of scene robot `name` (for `joints`), or npos.
  std::size_t robotIndex(const std::string& name) const;

 private:
  /// Contact `contact` is a pair the planner checks and it is not allowed now.
  bool refused(std::size_t contact, const std::vector<bool>& allowed) const;

  struct ContactGroups {
    std::size_t first = 0, second = 0;  // group indices in the modified scene
    bool checked = false;               // the planner checks this pair when it is not allowed
  };
  std::unique_ptr<planning::StateValidator> validator_;
  std::vector<std::shared_ptr<planning::RobotModel>> models_;  // in scene robot order
  std::vector<AllowedContact> contacts_;
  std::vector<ContactGroups> contact_groups_;
  double threshold_ = 0.0;
};

}  // namespace cobra::puncturing
