#pragma once
/// @file
/// isStateValid(q), q ∈ SE(3)×SE(3) (thesis Algorithms 4.2 and 5.1): inverse kinematics of every
/// robot, forward kinematics of every link, update of the collision world, distance queries between
/// the scene's group pairs; valid when every robot reaches its tools and every distance exceeds the
/// scene's min_collision_distance.

#include <cstddef>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/planning/collision_world.hpp"
#include "cobra/planning/robot_model.hpp"
#include "cobra/planning/scene.hpp"

namespace cobra::planning {

/// A state q ∈ SE(3)×SE(3): the two tool poses in the world frame [m, rad]. Puncturing: `first` is
/// the I-SUR needle tip, `second` the UR5 ultrasound probe; suturing: the right and left arm tools.
struct DualPose {
  KDL::Frame first = KDL::Frame::Identity();
  KDL::Frame second = KDL::Frame::Identity();
};

/// Why a state is valid or not.
enum class Validity {
  Valid,
  InvalidInput,  ///< a pose has a NaN/infinite value or a rotation that is not orthonormal
  Unreachable,   ///< the robot named in `robot` has no inverse kinematics solution
  TooClose,      ///< groups `first_group` and `second_group` are at `distance` <= the threshold
};

/// "valid", "invalid input", "unreachable", "too close".
const char* toString(Validity validity);

/// Outcome of one validity check. Names point into the validator's scene (valid while it lives).
struct ValidityResult {
  Validity validity = Validity::Valid;
  /// Unreachable: the robot's name.
  std::string_view robot;
  /// TooClose: the pair of groups and their closest objects; distance [m] (0 when touching).
  std::string_view first_group;
  std::string_view second_group;
  std::string_view first_object;
  std::string_view second_object;
  double distance = 0.0;
  bool valid() const { return validity == Validity::Valid; }
};

/// "too close: micro/environment 0.0012 m (needle/phantom)" and the like, for logs and events.
std::string describe(const ValidityResult& result);

/// Robot models by the names the scene gives its robots.
using RobotModels = std::map<std::string, std::shared_ptr<RobotModel>, std::less<>>;

/// Owns the collision world and the robot models of one scene. Not thread-safe.
class StateValidator {
 public:
  /// @throws std::invalid_argument if a scene robot has no model, a model's toolCount() differs
  ///         from the scene's `tools`, or an object is attached to a link the model does not have;
  ///         std::runtime_error if a mesh cannot be loaded.
  StateValidator(SceneDescription scene, RobotModels robots);

  /// Algorithm 4.2/5.1. No exception; the reason of the first failed check. On a scene made of
  /// primitives only, with robot models that do not allocate (robot_adapters.hpp), a check
  /// allocates nothing: the distance queries use FCL's own GJK (libccd's, FCL's default, allocates
  /// per query). Mesh objects go through FCL's BVH distance, which is not proven allocation-free.
  /// Checks run in the scene's `check` order; with `exact_distances` the reported distance of a
  /// TooClose is the exact minimum, otherwise the first pair found under the threshold.
  ValidityResult check(const DualPose& q, bool exact_distances = false);
  bool isStateValid(const DualPose& q) { return check(q).valid(); }

  /// Minimum over all checked pairs of their distance [m] for a reachable state (what the thesis'
  /// visualiser shows); +infinity if no pair is checked, NaN if q is unreachable or invalid.
  double minimumDistance(const DualPose& q);

  /// RobotModel::resetWarmStart() of every robot.
  void resetWarmStart();

  // ---- Joint space: a state is every robot's joints, concatenated in scene().robots order
  // (RobotModel::jointCount() values each; m, rad). Offered when every model offers joints.

  /// True when every robot model has joints (RobotModel::jointCount() > 0).
  bool hasJointSpace() const { return joint_space_; }
  /// Joints of all robots together.
  std::size_t jointCount() const { return joint_offsets_.back(); }
  /// Index of robot `robot`'s first joint in a joint state.
  std::size_t jointOffset(std::size_t robot) const { return joint_offsets_[robot]; }
  RobotModel& model(std::size_t robot) { return *models_[robot]; }
  /// Algorithm 4.2 without inverse kinematics: forward kinematics of every link, then the distance
  /// queries of check(). Unreachable when a robot's joints have no forward kinematics (outside the
  /// limits). No exception; no allocation on primitive scenes (as check()).
  /// `primitive_contacts_apart`: the scene's primitive contacts are allowed too (a state along a
  /// motion primitive, where the needle may be in the tissue).
  ValidityResult checkJoints(std::span<const double> q, bool exact_distances = false,
                             bool primitive_contacts_apart = false);
  /// The tool poses of joint state q in the world frame (the frames q of check() names). False
  /// when a robot's joints have no forward kinematics.
  bool toolPoses(std::span<const double> q, DualPose& tools);
  /// Every robot's RobotModel::inverseNear for the tool poses `tools` (world), seeded with the
  /// robot's joints in `seed` (empty: each model's configured seed), into `q`. On failure
  /// `failed_robot` is the robot's index in scene().robots. No allocation.
  Reachability inverseNear(const DualPose& tools, std::span<const double> seed, std::span<double> q,
                           std::size_t& failed_robot);
  /// The same with RobotModel::inverseGoal (seed = the start's joints).
  Reachability inverseGoal(const DualPose& tools, std::span<const double> start, std::span<double> q,
                           std::size_t& failed_robot);
  /// The goal with RobotModel::inverseGoalAlternative for every robot that has one and
  /// inverseGoal for the others; Unreachable (failed_robot = the robot count) when no robot has
  /// an alternative. No allocation.
  Reachability inverseGoalAlternative(const DualPose& tools, std::span<const double> start, std::span<double> q,
                                      std::size_t& failed_robot);
  /// Distances of a (measured) joint state [m]: `clearance` = the minimum over the checked pairs
  /// with the declared contacts left out (allowed and primitive: what the planner keeps above
  /// min_collision_distance along its paths, measured through the primitives too),
  /// `allowed_contact` = the minimum over the allowed contacts (the probe on the skin) and
  /// `primitive_contact` over the primitive contacts (the needle in the tissue); +infinity when the
  /// scene declares none. All NaN when q has no forward kinematics. Made for a measured state
  /// sampled along a motion: the closest pair of the last call is measured first and bounds the
  /// search of every pair.
  struct Distances {
    double clearance = 0.0;
    double allowed_contact = 0.0;
    double primitive_contact = 0.0;
  };
  /// `pairs`, when not empty: pairDistancesAt()'s values of the same placement as well (one FK
  /// or IK of the robots for both; NaNs with the rest).
  Distances distancesAt(std::span<const double> q, std::span<double> pairs = {});
  /// The same for tool poses q (each robot's IK from its configured seed); all NaN when q is
  /// unreachable or invalid.
  Distances distancesAt(const DualPose& q, std::span<double> pairs = {});

  /// The clearance per pair of groups, each robot against each other and against the patient:
  /// the scene's checked group pairs whose distance the robots' joints change, named
  /// "first/second" (scene().checks order). An object pair whose distance no joint changes (a
  /// robot base's fixed gap to the table) is left out, as are the declared contacts (allowed and
  /// primitive); a group pair with nothing left is left out whole. Found at construction: the
  /// distance of each object pair at the robots' seeds and at 32 seeded random joint states within
  /// their limits; a pair whose distance stays the same in all of them is static.
  const std::vector<std::string>& clearancePairs() const { return pair_names_; }
  /// Per clearancePairs() entry, the smallest distance [m] of its moving object pairs in joint
  /// state q into `out` (at least clearancePairs().size() values); false and NaNs when q has no
  /// forward kinematics. No exception; no allocation on primitive scenes (as check()).
  bool pairDistancesAt(std::span<const double> q, std::span<double> out);
  /// The same for tool poses q (each robot's IK from its configured seed).
  bool pairDistancesAt(const DualPose& q, std::span<double> out);

  const SceneDescription& scene() const { return world_.scene(); }
  const CollisionWorld& world() const { return world_; }

 private:
  /// Runs IK/FK of every robot and moves its objects; Valid or the first failure.
  ValidityResult placeRobots(const DualPose& q);
  /// FK of every robot from joints q, moves its objects; Valid or Unreachable.
  ValidityResult placeRobotsAt(std::span<const double> q);
  /// distancesAt() of the placed robots.
  Distances placedDistances();
  /// The same when `placed` (and the pair distances into `pairs`), all NaN otherwise.
  Distances placedDistances(bool placed, std::span<double> pairs);
  /// pairDistancesAt() of the placed robots.
  void placedPairDistances(std::span<double> out) const;
  /// clearancePairs() and their moving object pairs (at construction).
  void findMovingPairs();
  /// The distance queries of check() on the placed robots.
  ValidityResult checkDistances(ValidityResult result, bool exact_distances, bool primitive_contacts_apart = false);
  enum class Solve { Near, Goal, GoalAlternative };
  Reachability inverse(const DualPose& tools, std::span<const double> seed, std::span<double> q,
                       std::size_t& failed_robot, Solve solve);

  CollisionWorld world_;
  std::vector<std::shared_ptr<RobotModel>> models_;  // in scene().robots order
  std::vector<std::vector<KDL::Frame>> tools_;      // per robot, preallocated
  std::vector<std::vector<KDL::Frame>> tool_in_model_tool_;  // per robot and tool: the scene's tool frame
  std::vector<std::vector<KDL::Frame>> model_tool_in_tool_;  // the same, inverted
  std::vector<std::vector<KDL::Frame>> links_;      // per robot, preallocated
  std::vector<std::vector<double>> seeds_;           // per robot: its configured seed, preallocated
  /// Per robot: the joints placeRobotsAt last placed its objects at, while they are still placed
  /// there (placed_known_); a robot at the same joints again is not moved again (its FK, its
  /// objects' bounding boxes and its groups' broadphase trees): the measured state's clearance,
  /// sampled while one robot moves and the other holds still, and the planner's walks of one arm.
  std::vector<std::vector<double>> placed_joints_;  // preallocated
  std::vector<bool> placed_known_;
  std::vector<std::size_t> joint_offsets_{0};       // per robot, then the total
  bool joint_space_ = true;
  std::vector<std::string> pair_names_;  // clearancePairs()
  /// Per clearancePairs() entry: its object pairs (indices in scene().objects) that move apart.
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> pair_objects_;
  static constexpr std::size_t kNoObject = static_cast<std::size_t>(-1);
  std::pair<std::size_t, std::size_t> closest_{kNoObject, kNoObject};  // distancesAt's last closest objects
};

/// True when every element is finite and both rotations are orthonormal (to 1e-6).
bool isFinitePose(const DualPose& q);

}  // namespace cobra::planning
