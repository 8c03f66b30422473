#pragma once
/// @file
/// Scene description (the Model of the collision world): robot placements, collision groups,
/// objects and which group pairs the validator checks, read from a small line-based text format.
///
/// Format, one statement per line, `#` starts a comment, tokens separated by blanks; units m, rad;
/// a pose is `x y z roll pitch yaw` (KDL::Rotation::RPY: fixed axes X, Y, Z):
///
///     min_collision_distance 0.005                  # m, distance every checked pair must exceed
///     robot isur tools 0 base 0 0 0.8 0 0 0         # robot isur takes tool 0 of q; base in world
///     robot ur5 tools 1 base 0.6 0 0 0 0 3.1416     # `tools 0 1` for one solver of both tools
///     robot isur tools 0 base 0 0 0.8 0 0 0 tool 0 0 0 0 1.5708 0   # optional: the frame q names,
///                                                   # in the model's tool frame (every tool's)
///     tool isur 1 at 0 0 0.15 0 0 0                 # the frame of ONE tool of a robot: its index
///                                                   # among the robot's tools (the order of its
///                                                   # `tools`, from 0), in that tool's model frame
///     group environment                             # one FCL broadphase manager per group
///     object table environment world box 1.2 0.8 0.04 at 0 0 -0.02 0 0 0
///     object column macro isur.0 cylinder 0.03 0.4 at 0 0 0 0 0 0
///     object tip micro isur.1 capsule 0.002 0.1 at 0 0 0.05 0 0 0
///     object probe ur5 ur5.2 sphere 0.03 at 0 0 0 0 0 0
///     object phantom environment world mesh phantom.stl scale 0.001 at 0 0 0 0 0 0
///     check macro micro                             # a distance query of the validator
///     allow us_probe phantom                        # a contact the task requires: this object
///                                                   # pair is left out of every distance query
///     primitive_contact needle phantom              # a contact only the motion primitives make:
///                                                   # planned states keep the clearance from it,
///                                                   # the measured clearance reports it apart
///
/// `object NAME GROUP ATTACH SHAPE ... at POSE`: ATTACH is `world` or `ROBOT.LINK` (link index as
/// the robot model reports it); the pose is the shape frame in the attachment frame. Mesh paths are
/// relative to the scene file. Names are unique per kind; groups and robots are declared before use.
/// A `tool` statement overrides the robot line's `tool` for that tool; one tool's frame is given by
/// at most one `tool` statement.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/planning/geometry.hpp"

namespace cobra::planning {

/// Where a robot stands and which components of q its solver takes.
struct RobotPlacement {
  std::string name;
  /// Robot base frame in the world frame [m, rad].
  KDL::Frame base_in_world = KDL::Frame::Identity();
  /// Indices (0 = first, 1 = second pose of q ∈ SE(3)×SE(3)) in the order the solver takes them.
  std::vector<std::size_t> tool_indices;
  /// Per tool of the robot (the order of tool_indices, i.e. the robot model's tools): the frame
  /// its pose of q gives, in the model's frame of that tool [m, rad] (e.g. an application whose
  /// needle frames have z along the needle, where the model's needle is x; the tip of a stick the
  /// gripper holds, where the model's tool is the gripper). Empty: identity for every tool.
  std::vector<KDL::Frame> tool_frames;

  /// tool_frames[tool], identity when tool_frames is empty.
  KDL::Frame toolFrame(std::size_t tool) const {
    return tool_frames.empty() ? KDL::Frame::Identity() : tool_frames.at(tool);
  }
  /// Sets the frame of tool `tool` (< tool_indices.size()), the others kept (identity if unset).
  void setToolFrame(std::size_t tool, const KDL::Frame& frame) {
    tool_frames.resize(tool_indices.size(), KDL::Frame::Identity());
    tool_frames.at(tool) = frame;
  }
};

/// A distance query between two groups (Algorithm 4.2, lines 8-12).
struct GroupPair {
  std::size_t first = 0;
  std::size_t second = 0;
};

/// Immutable description of a planning scene. Build it with parseScene()/loadScene() or by hand
/// and validate it with validate().
struct SceneDescription {
  /// Every checked pair must be farther apart than this [m] for a state to be valid.
  double min_collision_distance = 0.0;
  std::vector<RobotPlacement> robots;
  std::vector<std::string> groups;
  std::vector<ObjectDescription> objects;
  std::vector<GroupPair> checks;
  /// Object pairs (by name) whose distance is never checked: the contacts the task
  /// requires (thesis §4.5: "the only contacts allowed are those required by the task"), e.g. the
  /// ultrasound probe pressed on the phantom while the other robot plans.
  std::vector<std::pair<std::string, std::string>> allowed_contacts;
  /// Object pairs (by name) in contact only during the task's motion primitives, never along a
  /// planned path (e.g. the needle through the skin into the tissue: the descent, the insertion
  /// and the extraction are straight motions, not planned). The validity check keeps them at
  /// min_collision_distance like any checked pair (a plan never takes the needle into the
  /// phantom); the measured clearance (StateValidator::distancesAt) leaves them out and reports
  /// their distance apart.
  std::vector<std::pair<std::string, std::string>> primitive_contacts;
  /// Index of an object by name; npos when absent.
  std::size_t objectIndex(std::string_view name) const;

  /// Index of a group or robot by name; npos when absent.
  std::size_t groupIndex(std::string_view name) const;
  std::size_t robotIndex(std::string_view name) const;
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);

  /// Checks names, references and dimensions.
  /// @throws std::invalid_argument naming the offending element.
  void validate() const;
};

/// Parses scene text; `source` names it in errors ("file:line: ...") and `base_dir` resolves mesh
/// paths. @throws std::invalid_argument on any syntax or reference error.
SceneDescription parseScene(std::string_view text, const std::string& source, const std::filesystem::path& base_dir);

/// Reads and parses a scene file. @throws std::runtime_error if unreadable, std::invalid_argument
/// on bad content.
SceneDescription loadScene(const std::filesystem::path& path);

}  // namespace cobra::planning
