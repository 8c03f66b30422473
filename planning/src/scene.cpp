#include "cobra/planning/scene.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace cobra::planning {

std::size_t SceneDescription::groupIndex(std::string_view name) const {
  const auto it = std::find(groups.begin(), groups.end(), name);
  return it == groups.end() ? npos : static_cast<std::size_t>(it - groups.begin());
}

std::size_t SceneDescription::objectIndex(std::string_view name) const {
  const auto it =
      std::find_if(objects.begin(), objects.end(), [&](const ObjectDescription& o) { return o.name == name; });
  return it == objects.end() ? npos : static_cast<std::size_t>(it - objects.begin());
}

std::size_t SceneDescription::robotIndex(std::string_view name) const {
  const auto it = std::find_if(robots.begin(), robots.end(), [&](const RobotPlacement& r) { return r.name == name; });
  return it == robots.end() ? npos : static_cast<std::size_t>(it - robots.begin());
}

namespace {

std::string where(const ObjectDescription& object) {
  return object.origin.empty() ? "object '" + object.name + "'" : object.origin + ": object '" + object.name + "'";
}

bool positiveFinite(double value) { return value > 0.0 && std::isfinite(value); }

}  // namespace

void SceneDescription::validate() const {
  if (!(min_collision_distance >= 0.0) || !std::isfinite(min_collision_distance))
    throw std::invalid_argument("scene: min_collision_distance must be a finite distance >= 0 m");
  for (std::size_t i = 0; i < robots.size(); ++i) {
    const RobotPlacement& robot = robots[i];
    if (robotIndex(robot.name) != i) throw std::invalid_argument("scene: robot '" + robot.name + "' declared twice");
    if (robot.tool_indices.empty() || robot.tool_indices.size() > 2)
      throw std::invalid_argument("scene: robot '" + robot.name + "' must take one or two tools of q (0 and/or 1)");
    for (const std::size_t tool : robot.tool_indices)
      if (tool > 1) throw std::invalid_argument("scene: robot '" + robot.name + "': tool index must be 0 or 1");
    if (!robot.tool_frames.empty() && robot.tool_frames.size() != robot.tool_indices.size())
      throw std::invalid_argument("scene: robot '" + robot.name + "' has " + std::to_string(robot.tool_indices.size()) +
                                  " tool(s) but " + std::to_string(robot.tool_frames.size()) +
                                  " tool frames: give one per tool (or none: identity)");
  }
  for (std::size_t i = 0; i < groups.size(); ++i)
    if (groupIndex(groups[i]) != i) throw std::invalid_argument("scene: group '" + groups[i] + "' declared twice");
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const ObjectDescription& object = objects[i];
    for (std::size_t j = 0; j < i; ++j)
      if (objects[j].name == object.name) throw std::invalid_argument(where(object) + " declared twice");
    if (groupIndex(object.group) == npos)
      throw std::invalid_argument(where(object) + ": unknown group '" + object.group + "' (declare it with `group`)");
    if (!object.attached_to.isWorld() && robotIndex(object.attached_to.robot_name) == npos)
      throw std::invalid_argument(where(object) + ": unknown robot '" + object.attached_to.robot_name +
                                  "' (declare it with `robot`)");
    const ShapeDescription& shape = object.shape;
    const std::size_t used = shape.kind == ShapeKind::Box                                        ? 3
                             : shape.kind == ShapeKind::Sphere                                   ? 1
                             : shape.kind == ShapeKind::Cylinder || shape.kind == ShapeKind::Capsule ? 2
                                                                                                 : 0;
    for (std::size_t d = 0; d < used; ++d)
      if (!positiveFinite(shape.dimensions[d]))
        throw std::invalid_argument(where(object) + ": " + toString(shape.kind) + " dimensions must be > 0 m");
    if (shape.kind == ShapeKind::Mesh && !positiveFinite(shape.mesh_scale))
      throw std::invalid_argument(where(object) + ": mesh scale must be > 0");
  }
  for (const GroupPair& pair : checks)
    if (pair.first >= groups.size() || pair.second >= groups.size() || pair.first == pair.second)
      throw std::invalid_argument("scene: a check must name two different declared groups");
  for (const auto& [a, b] : allowed_contacts)
    if (objectIndex(a) == npos || objectIndex(b) == npos || a == b)
      throw std::invalid_argument("scene: allowed contact '" + a + "'-'" + b +
                                  "' must name two different declared objects");
  for (const auto& [a, b] : primitive_contacts)
    if (objectIndex(a) == npos || objectIndex(b) == npos || a == b)
      throw std::invalid_argument("scene: primitive contact '" + a + "'-'" + b +
                                  "' must name two different declared objects");
}

namespace {

/// Tokens of one line with the cursor the statement parsers consume.
class Line {
 public:
  Line(std::string_view text, std::string location) : location_(std::move(location)) {
    std::size_t i = 0;
    while (i < text.size()) {
      while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r')) ++i;
      std::size_t j = i;
      while (j < text.size() && text[j] != ' ' && text[j] != '\t' && text[j] != '\r') ++j;
      if (j > i) tokens_.push_back(text.substr(i, j - i));
      i = j;
    }
  }
  bool empty() const { return tokens_.empty(); }
  bool atEnd() const { return next_ == tokens_.size(); }
  std::string_view peek() const { return atEnd() ? std::string_view{} : tokens_[next_]; }

  std::string_view word(const char* what) {
    if (atEnd()) fail(std::string("expected ") + what + " at the end of the line");
    return tokens_[next_++];
  }
  void keyword(std::string_view expected) {
    const std::string_view got = word(std::string(expected).c_str());
    if (got != expected) fail("expected '" + std::string(expected) + "', found '" + std::string(got) + "'");
  }
  double number(const char* what) {
    const std::string_view text = word(what);
    double value = 0.0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc{} || end != text.data() + text.size() || !std::isfinite(value))
      fail(std::string("expected ") + what + " (a finite number), found '" + std::string(text) + "'");
    return value;
  }
  std::size_t index(const char* what) {
    const std::string_view text = word(what);
    std::size_t value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc{} || end != text.data() + text.size())
      fail(std::string("expected ") + what + " (a non-negative integer), found '" + std::string(text) + "'");
    return value;
  }
  KDL::Frame pose() {
    const double x = number("x [m]"), y = number("y [m]"), z = number("z [m]");
    const double roll = number("roll [rad]"), pitch = number("pitch [rad]"), yaw = number("yaw [rad]");
    return KDL::Frame(KDL::Rotation::RPY(roll, pitch, yaw), KDL::Vector(x, y, z));
  }
  void end() {
    if (!atEnd()) fail("unexpected '" + std::string(peek()) + "' at the end of the statement");
  }
  [[noreturn]] void fail(const std::string& message) const { throw std::invalid_argument(location_ + ": " + message); }
  const std::string& location() const { return location_; }

 private:
  std::vector<std::string_view> tokens_;
  std::size_t next_ = 0;
  std::string location_;
};

ShapeDescription parseShape(Line& line, const std::filesystem::path& base_dir) {
  ShapeDescription shape;
  const std::string_view kind = line.word("a shape (box, cylinder, capsule, sphere, mesh)");
  if (kind == "box") {
    shape.kind = ShapeKind::Box;
    shape.dimensions = {line.number("size x [m]"), line.number("size y [m]"), line.number("size z [m]")};
  } else if (kind == "cylinder" || kind == "capsule") {
    shape.kind = kind == "cylinder" ? ShapeKind::Cylinder : ShapeKind::Capsule;
    shape.dimensions = {line.number("radius [m]"), line.number("length [m]"), 0.0};
  } else if (kind == "sphere") {
    shape.kind = ShapeKind::Sphere;
    shape.dimensions = {line.number("radius [m]"), 0.0, 0.0};
  } else if (kind == "mesh") {
    shape.kind = ShapeKind::Mesh;
    const std::filesystem::path file(std::string(line.word("a mesh file (STL or OBJ)")));
    shape.mesh_path = file.is_absolute() ? file : base_dir / file;
    std::error_code error;
    if (!std::filesystem::is_regular_file(shape.mesh_path, error))
      line.fail("mesh file '" + shape.mesh_path.string() + "' not found (paths are relative to the scene file)");
    if (line.peek() == "scale") {
      line.keyword("scale");
      shape.mesh_scale = line.number("scale [m per file unit]");
    }
  } else {
    line.fail("unknown shape '" + std::string(kind) + "' (box, cylinder, capsule, sphere, mesh)");
  }
  return shape;
}

Attachment parseAttachment(Line& line, const SceneDescription& scene) {
  const std::string_view text = line.word("`world` or ROBOT.LINK");
  if (text == "world") return {};
  const std::size_t dot = text.rfind('.');
  if (dot == std::string_view::npos) line.fail("expected `world` or ROBOT.LINK, found '" + std::string(text) + "'");
  Attachment attachment;
  attachment.robot_name = std::string(text.substr(0, dot));
  if (scene.robotIndex(attachment.robot_name) == SceneDescription::npos)
    line.fail("unknown robot '" + attachment.robot_name + "' (declare it with `robot` first)");
  Line index_line(text.substr(dot + 1), line.location());
  attachment.link_index = index_line.index("a link index");
  return attachment;
}

/// `tools 0 1` as written, for messages.
std::string toolsText(const RobotPlacement& robot) {
  std::string text = "tools";
  for (const std::size_t tool : robot.tool_indices) text += " " + std::to_string(tool);
  return text;
}

/// Parse state across lines: the (robot, tool) pairs a `tool` statement has given.
using ToolsGiven = std::vector<std::pair<std::size_t, std::size_t>>;

void parseToolStatement(Line& line, SceneDescription& scene, ToolsGiven& given) {
  const std::string name(line.word("a robot name"));
  const std::size_t r = scene.robotIndex(name);
  if (r == SceneDescription::npos) line.fail("unknown robot '" + name + "' (declare it with `robot` first)");
  RobotPlacement& robot = scene.robots[r];
  const std::size_t tool = line.index("a tool index of the robot");
  const std::size_t count = robot.tool_indices.size();
  if (tool >= count)
    line.fail("robot '" + name + "' has " + std::to_string(count) + " tool" + (count == 1 ? "" : "s") + " (`" +
              toolsText(robot) + "`): no tool " + std::to_string(tool) +
              " (a tool index counts the robot's tools from 0, in the order of its `tools`)");
  if (std::find(given.begin(), given.end(), std::pair{r, tool}) != given.end())
    line.fail("tool " + std::to_string(tool) + " of robot '" + name + "' given twice");
  given.emplace_back(r, tool);
  line.keyword("at");
  robot.setToolFrame(tool, line.pose());
}

void parseStatement(Line& line, SceneDescription& scene, const std::filesystem::path& base_dir, ToolsGiven& tools) {
  const std::string_view statement = line.word("a statement");
  if (statement == "min_collision_distance") {
    scene.min_collision_distance = line.number("a distance [m]");
    if (scene.min_collision_distance < 0.0) line.fail("min_collision_distance must be >= 0 m");
  } else if (statement == "robot") {
    RobotPlacement robot;
    robot.name = std::string(line.word("a robot name"));
    if (scene.robotIndex(robot.name) != SceneDescription::npos) line.fail("robot '" + robot.name + "' declared twice");
    line.keyword("tools");
    while (line.peek() != "base" && !line.atEnd()) {
      const std::size_t tool = line.index("a tool index (0 or 1)");
      if (tool > 1) line.fail("tool index must be 0 (first pose of q) or 1 (second pose)");
      if (std::find(robot.tool_indices.begin(), robot.tool_indices.end(), tool) != robot.tool_indices.end())
        line.fail("tool " + std::to_string(tool) + " listed twice");
      robot.tool_indices.push_back(tool);
    }
    if (robot.tool_indices.empty() || robot.tool_indices.size() > 2) line.fail("a robot takes one or two tools");
    line.keyword("base");
    robot.base_in_world = line.pose();
    if (!line.atEnd()) {
      line.keyword("tool");
      robot.tool_frames.assign(robot.tool_indices.size(), line.pose());
    }
    scene.robots.push_back(std::move(robot));
  } else if (statement == "tool") {
    parseToolStatement(line, scene, tools);
  } else if (statement == "group") {
    const std::string name(line.word("a group name"));
    if (scene.groupIndex(name) != SceneDescription::npos) line.fail("group '" + name + "' declared twice");
    scene.groups.push_back(name);
  } else if (statement == "object") {
    ObjectDescription object;
    object.origin = line.location();
    object.name = std::string(line.word("an object name"));
    for (const ObjectDescription& other : scene.objects)
      if (other.name == object.name) line.fail("object '" + object.name + "' declared twice");
    object.group = std::string(line.word("a group name"));
    if (scene.groupIndex(object.group) == SceneDescription::npos)
      line.fail("unknown group '" + object.group + "' (declare it with `group` first)");
    object.attached_to = parseAttachment(line, scene);
    object.shape = parseShape(line, base_dir);
    line.keyword("at");
    object.offset = line.pose();
    scene.objects.push_back(std::move(object));
  } else if (statement == "check") {
    GroupPair pair;
    for (std::size_t* slot : {&pair.first, &pair.second}) {
      const std::string name(line.word("a group name"));
      *slot = scene.groupIndex(name);
      if (*slot == SceneDescription::npos) line.fail("unknown group '" + name + "' (declare it with `group` first)");
    }
    if (pair.first == pair.second) line.fail("a check needs two different groups");
    scene.checks.push_back(pair);
  } else if (statement == "allow" || statement == "primitive_contact") {
    const bool allow = statement == "allow";
    std::string pair[2];
    for (std::string& name : pair) {
      name = std::string(line.word("an object name"));
      if (scene.objectIndex(name) == SceneDescription::npos)
        line.fail("unknown object '" + name + "' (declare it with `object` first)");
    }
    if (pair[0] == pair[1])
      line.fail(std::string(allow ? "an allowed" : "a primitive") + " contact needs two different objects");
    (allow ? scene.allowed_contacts : scene.primitive_contacts).emplace_back(pair[0], pair[1]);
  } else {
    line.fail("unknown statement '" + std::string(statement) +
              "' (min_collision_distance, robot, tool, group, object, check, allow, primitive_contact)");
  }
  line.end();
}

}  // namespace

SceneDescription parseScene(std::string_view text, const std::string& source, const std::filesystem::path& base_dir) {
  SceneDescription scene;
  ToolsGiven tools;
  std::size_t line_number = 0;
  while (!text.empty()) {
    ++line_number;
    const std::size_t newline = text.find('\n');
    std::string_view content = text.substr(0, newline);
    text = newline == std::string_view::npos ? std::string_view{} : text.substr(newline + 1);
    content = content.substr(0, content.find('#'));
    Line line(content, source + ":" + std::to_string(line_number));
    if (!line.empty()) parseStatement(line, scene, base_dir, tools);
  }
  scene.validate();
  return scene;
}

SceneDescription loadScene(const std::filesystem::path& path) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error("cannot read scene file '" + path.string() + "': check the path");
  std::ostringstream text;
  text << file.rdbuf();
  return parseScene(text.str(), path.string(), path.parent_path());
}

}  // namespace cobra::planning
