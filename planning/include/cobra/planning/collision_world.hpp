#pragma once
/// @file
/// The collision world (the Data of a scene): one FCL broadphase manager (dynamic AABB tree) per
/// group, collision objects built once from the scene's geometry, link transforms updated from the
/// robots' forward kinematics, minimum-distance queries between groups (thesis §4.5.1).

#include <cstddef>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/planning/scene.hpp"

namespace cobra::planning {

/// Result of a minimum-distance query between two groups.
struct GroupDistance {
  /// Minimum distance [m]; 0 when the groups touch or interpenetrate; +infinity when a group is
  /// empty.
  double distance = 0.0;
  /// The closest objects (names from the scene); empty when a group is empty.
  std::string_view first_object;
  std::string_view second_object;
  /// The closest objects' indices in scene().objects; npos when a group is empty.
  std::size_t first_index = static_cast<std::size_t>(-1);
  std::size_t second_index = static_cast<std::size_t>(-1);
};

/// Preallocated FCL objects and managers for one scene. Not thread-safe: one per planner thread.
class CollisionWorld {
 public:
  /// Builds every object (loading meshes) and registers it with its group's manager. Objects
  /// attached to robots start at the robot base until the first setRobotLinks().
  /// @throws std::invalid_argument if the scene is inconsistent, std::runtime_error if a mesh
  ///         cannot be loaded (the message names the object, its scene line and the file).
  explicit CollisionWorld(SceneDescription scene);
  ~CollisionWorld();
  CollisionWorld(const CollisionWorld&) = delete;
  CollisionWorld& operator=(const CollisionWorld&) = delete;

  const SceneDescription& scene() const { return scene_; }

  /// Highest link index the scene attaches an object to on `robot`, plus one (0 if none).
  std::size_t linksUsedBy(std::size_t robot) const;

  /// Moves every object attached to robot `robot` (index in scene().robots).
  /// @param links_in_world  link frames in the world frame [m, rad]; at least linksUsedBy(robot).
  /// Updates the affected managers (FCL refits and rebalances their trees).
  void setRobotLinks(std::size_t robot, std::span<const KDL::Frame> links_in_world);

  /// Minimum distance between groups `first` and `second` (indices in scene().groups).
  /// `stop_below` [m]: a validity threshold. The search stops at the first pair found at or under
  /// it (the returned distance is then that pair's, an upper bound of the minimum) and skips pairs
  /// that cannot be under it: a returned distance above `stop_below` is only known to be above it
  /// (+infinity when every pair was skipped). Pass 0 for the exact minimum.
  /// `primitive_contacts_apart`: leave the scene's primitive contacts out too (the measured
  /// clearance; the validity check keeps them in).
  GroupDistance distance(std::size_t first, std::size_t second, double stop_below = 0.0,
                         bool primitive_contacts_apart = false) const;

  /// The exact minimum distance between groups `first` and `second` when it is under `bound` [m];
  /// otherwise distance = `bound` and no closest objects. Pairs whose bounding boxes are `bound`
  /// or more apart are never measured, so a caller that already knows a distance at least the
  /// minimum (another group pair's, the closest pair of its last query) skips most of the narrow
  /// phase: the minimum over several queries, each bounded by the smallest before it, is the
  /// minimum of unbounded queries.
  GroupDistance distanceUnder(std::size_t first, std::size_t second, double bound,
                              bool primitive_contacts_apart = false) const;

  /// Distance between objects `a` and `b` (indices in scene().objects) [m], 0 when touching or
  /// interpenetrating; whether or not the scene checks or allows the pair.
  double objectDistance(std::size_t a, std::size_t b) const;

  /// Minimum distance over the scene's allowed contacts (object pairs left out of distance()) [m]:
  /// how deep the probe presses into the skin is not a clearance, but still worth reporting apart.
  /// 0 when touching or interpenetrating; +infinity when the scene declares none.
  double allowedContactDistance() const;
  /// The same over the scene's primitive contacts (the needle in the tissue) [m].
  double primitiveContactDistance() const;

  /// World pose of object `object` (index in scene().objects), e.g. for a visualiser.
  KDL::Frame objectPose(std::size_t object) const;

 private:
  GroupDistance query(std::size_t first, std::size_t second, double stop_below, double bound,
                      bool primitive_contacts_apart) const;

  struct Impl;
  SceneDescription scene_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cobra::planning
