#pragma once
/// @file
/// Geometry of the collision world as plain data: primitives (box, cylinder, capsule, sphere) and
/// triangle meshes read from STL or OBJ files. The same description feeds the collision world and,
/// later, a visualiser; nothing here depends on FCL.

#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <kdl/frames.hpp>

namespace cobra::planning {

/// Kind of a shape. Cylinders and capsules are centred on their frame, axis along its z.
enum class ShapeKind { Box, Cylinder, Capsule, Sphere, Mesh };

/// "box", "cylinder", "capsule", "sphere", "mesh".
const char* toString(ShapeKind kind);

/// One shape, in its own frame.
struct ShapeDescription {
  ShapeKind kind = ShapeKind::Box;
  /// Box: full side lengths x, y, z [m]. Cylinder/capsule: radius [m], length [m] (of the straight
  /// part for a capsule). Sphere: radius [m]. Mesh: unused.
  std::array<double, 3> dimensions{};
  /// Mesh: absolute path of the STL or OBJ file (the scene parser resolves relative paths).
  std::filesystem::path mesh_path;
  /// Mesh: factor from file units to m (0.001 for a CAD export in mm).
  double mesh_scale = 1.0;
};

/// Where an object is fixed: to the world, or to link `link_index` of robot `robot_name`.
struct Attachment {
  /// Empty for the world frame.
  std::string robot_name;
  /// Index into the link frames the robot model reports (see RobotModel::linkCount).
  std::size_t link_index = 0;
  bool isWorld() const { return robot_name.empty(); }
};

/// One collision object: a shape at a fixed pose in the frame it is attached to.
struct ObjectDescription {
  std::string name;
  /// Name of the collision group (one FCL broadphase manager) the object belongs to.
  std::string group;
  Attachment attached_to;
  /// Pose of the shape's frame in the attachment frame (world or link) [m, rad].
  KDL::Frame offset = KDL::Frame::Identity();
  ShapeDescription shape;
  /// Where the object was declared ("scene.txt:12"), for error messages; empty if built in code.
  std::string origin;
};

/// A triangle mesh in file coordinates multiplied by the scale: vertices [m] and index triples.
struct TriangleMesh {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<std::size_t, 3>> triangles;
};

/// Reads an STL (ASCII or binary) or OBJ file with assimp and scales it to m.
/// @throws std::runtime_error naming the file when it is missing, unreadable, malformed or has
///         no triangles.
TriangleMesh loadMesh(const std::filesystem::path& path, double scale);

}  // namespace cobra::planning
