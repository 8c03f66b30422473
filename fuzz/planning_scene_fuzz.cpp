// libFuzzer target: the planning scene text format (cobra::planning::parseScene,
// planning/include/cobra/planning/scene.hpp). Checks that any text either parses into a scene that
// passes validate() or is refused with std::invalid_argument whose message names the source and,
// when it names a line, a line of the text; that a parsed scene, printed back into the format,
// parses to the same scene (numbers exactly; rotations, printed as roll pitch yaw, within 1e-9);
// and that nothing crashes. Mesh paths resolve against planning/test/data (COBRA_FUZZ_SCENE_DIR),
// where the seed scene's mesh lives.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>

#include "cobra/planning/scene.hpp"
#include "fuzz_support.hpp"

namespace {

using cobra::fuzz::exact;
using cobra::fuzz::sameFrame;
using cobra::planning::SceneDescription;
using cobra::planning::ShapeKind;

std::string pose(const KDL::Frame& frame) {
  double roll = 0, pitch = 0, yaw = 0;
  frame.M.GetRPY(roll, pitch, yaw);
  return exact(frame.p.x()) + " " + exact(frame.p.y()) + " " + exact(frame.p.z()) + " " + exact(roll) + " " +
         exact(pitch) + " " + exact(yaw);
}

std::string shape(const cobra::planning::ShapeDescription& s) {
  const auto& d = s.dimensions;
  switch (s.kind) {
    case ShapeKind::Box: return "box " + exact(d[0]) + " " + exact(d[1]) + " " + exact(d[2]);
    case ShapeKind::Cylinder: return "cylinder " + exact(d[0]) + " " + exact(d[1]);
    case ShapeKind::Capsule: return "capsule " + exact(d[0]) + " " + exact(d[1]);
    case ShapeKind::Sphere: return "sphere " + exact(d[0]);
    case ShapeKind::Mesh: return "mesh " + s.mesh_path.string() + " scale " + exact(s.mesh_scale);
  }
  std::abort();
}

/// The scene in the text format, declarations before their use.
std::string print(const SceneDescription& scene) {
  std::string out = "min_collision_distance " + exact(scene.min_collision_distance) + "\n";
  for (const auto& robot : scene.robots) {
    out += "robot " + robot.name + " tools";
    for (const std::size_t tool : robot.tool_indices) out += " " + std::to_string(tool);
    out += " base " + pose(robot.base_in_world) + "\n";
    for (std::size_t t = 0; t < robot.tool_indices.size(); ++t)
      out += "tool " + robot.name + " " + std::to_string(t) + " at " + pose(robot.toolFrame(t)) + "\n";
  }
  for (const auto& group : scene.groups) out += "group " + group + "\n";
  for (const auto& object : scene.objects) {
    const std::string attach = object.attached_to.isWorld()
                                   ? "world"
                                   : object.attached_to.robot_name + "." + std::to_string(object.attached_to.link_index);
    out += "object " + object.name + " " + object.group + " " + attach + " " + shape(object.shape) + " at " +
           pose(object.offset) + "\n";
  }
  for (const auto& check : scene.checks) out += "check " + scene.groups[check.first] + " " + scene.groups[check.second] + "\n";
  for (const auto& [a, b] : scene.allowed_contacts) out += "allow " + a + " " + b + "\n";
  for (const auto& [a, b] : scene.primitive_contacts) out += "primitive_contact " + a + " " + b + "\n";
  return out;
}

bool same(const SceneDescription& a, const SceneDescription& b) {
  if (a.min_collision_distance != b.min_collision_distance || a.groups != b.groups ||
      a.allowed_contacts != b.allowed_contacts || a.primitive_contacts != b.primitive_contacts ||
      a.robots.size() != b.robots.size() ||
      a.objects.size() != b.objects.size() || a.checks.size() != b.checks.size())
    return false;
  for (std::size_t i = 0; i < a.robots.size(); ++i) {
    const auto &x = a.robots[i], &y = b.robots[i];
    if (x.name != y.name || x.tool_indices != y.tool_indices || !sameFrame(x.base_in_world, y.base_in_world))
      return false;
    for (std::size_t t = 0; t < x.tool_indices.size(); ++t)
      if (!sameFrame(x.toolFrame(t), y.toolFrame(t))) return false;
  }
  for (std::size_t i = 0; i < a.objects.size(); ++i) {
    const auto &x = a.objects[i], &y = b.objects[i];
    if (x.name != y.name || x.group != y.group || x.attached_to.robot_name != y.attached_to.robot_name ||
        x.attached_to.link_index != y.attached_to.link_index || !sameFrame(x.offset, y.offset) ||
        x.shape.kind != y.shape.kind || x.shape.dimensions != y.shape.dimensions ||
        x.shape.mesh_path != y.shape.mesh_path || x.shape.mesh_scale != y.shape.mesh_scale)
      return false;
  }
  for (std::size_t i = 0; i < a.checks.size(); ++i)
    if (a.checks[i].first != b.checks[i].first || a.checks[i].second != b.checks[i].second) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  SceneDescription scene;
  try {
    scene = cobra::planning::parseScene(text, "fuzz.scene", COBRA_FUZZ_SCENE_DIR);
  } catch (const std::invalid_argument& e) {
    cobra::fuzz::requireLocated(e.what(), "fuzz.scene", text);
    return 0;
  }
  try {
    scene.validate();  // what the parser accepts is a valid scene
    if (!same(cobra::planning::parseScene(print(scene), "printed", COBRA_FUZZ_SCENE_DIR), scene)) std::abort();
  } catch (const std::invalid_argument&) {
    std::abort();  // validate() refuses a parsed scene, or the parser refuses the text of a scene it accepted
  }
  return 0;
}
