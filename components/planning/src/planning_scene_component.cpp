#include "cobra/components/planning/planning_scene_component.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "cobra/planning/geometry.hpp"
#include "cobra/planning/robot_adapters.hpp"

namespace cobra::components {

namespace {

namespace fs = std::filesystem;
using planning::ObjectDescription;
using planning::SceneDescription;

std::vector<std::string> splitNames(const std::string& text) {
  std::vector<std::string> names;
  std::string current;
  for (const char c : text + " ") {
    if (c == ' ' || c == ',' || c == '\t' || c == '\n') {
      if (!current.empty()) names.push_back(current);
      current.clear();
    } else {
      current += c;
    }
  }
  return names;
}

fs::path resolve(const std::string& folder, const std::string& file) {
  const fs::path path(file);
  return path.is_absolute() || folder.empty() ? path : fs::path(folder) / path;
}

/// A mesh shape for `name`, loaded once to check it. @throws std::invalid_argument naming `property`.
planning::ShapeDescription meshShape(const PlanningSceneSettings& s, const std::string& name, const char* property) {
  planning::ShapeDescription shape;
  shape.kind = planning::ShapeKind::Mesh;
  shape.mesh_path = resolve(s.models_folder, name);
  shape.mesh_scale = s.mesh_scale;
  if (!fs::exists(shape.mesh_path))
    throw std::invalid_argument(std::string("property ") + property + ": mesh file '" + shape.mesh_path.string() +
                                "' does not exist (names are relative to models_folder)");
  try {
    planning::loadMesh(shape.mesh_path, shape.mesh_scale);
  } catch (const std::exception& error) {
    throw std::invalid_argument(std::string("property ") + property + ": " + error.what());
  }
  return shape;
}

/// Link indices of a list property (non-negative integers). @throws naming `property`.
std::vector<std::size_t> linkIndices(const std::vector<double>& values, const char* property) {
  std::vector<std::size_t> links;
  for (const double v : values) {
    if (!(v >= 0.0) || v != std::floor(v) || v > 64.0)
      throw std::invalid_argument(std::string("property ") + property + ": " + std::to_string(v) +
                                  " is not a link index (an integer from 0)");
    links.push_back(static_cast<std::size_t>(v));
  }
  return links;
}

bool contains(const std::vector<std::size_t>& list, std::size_t value) {
  return std::find(list.begin(), list.end(), value) != list.end();
}

void replaceRobotMeshes(SceneDescription& scene, const PlanningSceneSettings& s, const std::string& robot,
                        const std::string& names, const char* property) {
  const std::vector<std::string> meshes = splitNames(names);
  if (meshes.empty()) return;
  if (scene.robotIndex(robot) == SceneDescription::npos)
    throw std::invalid_argument(std::string("property ") + property + ": the scene has no robot '" + robot + "'");
  for (std::size_t link = 0; link < meshes.size(); ++link) {
    if (meshes[link] == "-") continue;
    const auto on_link = [&](const ObjectDescription& o) {
      return o.attached_to.robot_name == robot && o.attached_to.link_index == link;
    };
    const auto first = std::find_if(scene.objects.begin(), scene.objects.end(), on_link);
    if (first == scene.objects.end())
      throw std::invalid_argument(std::string("property ") + property + ": link " + std::to_string(link) + " of '" +
                                  robot + "' has no object in the scene to take the mesh's group from");
    ObjectDescription mesh = *first;
    mesh.name = robot + "_link_" + std::to_string(link);
    mesh.offset = KDL::Frame::Identity();
    mesh.shape = meshShape(s, meshes[link], property);
    mesh.origin = std::string("property ") + property;
    std::erase_if(scene.objects, on_link);
    scene.objects.push_back(mesh);
  }
}

}  // namespace

SceneDescription buildPlanningScene(const PlanningSceneSettings& s) {
  if (s.scene_file.empty())
    throw std::invalid_argument(
        "property scene_file is empty: give a scene file (format: cobra/planning/scene.hpp)");
  SceneDescription scene;
  try {
    scene = planning::loadScene(resolve(s.models_folder, s.scene_file));
  } catch (const std::exception& error) {
    throw std::invalid_argument(std::string("property scene_file: ") + error.what());
  }
  if (!(s.mesh_scale > 0.0) || !std::isfinite(s.mesh_scale))
    throw std::invalid_argument("property mesh_scale: must be a positive number of m per mesh unit");

  replaceRobotMeshes(scene, s, "isur", s.isur_mesh_names, "isur_mesh_names");
  replaceRobotMeshes(scene, s, "ur5", s.ur5_mesh_names, "UR5_mesh_names");
  const std::vector<std::string> env = splitNames(s.env_mesh_names);
  std::size_t k = 0;
  for (ObjectDescription& object : scene.objects) {
    if (object.group != "environment" || k >= env.size()) continue;
    if (env[k] != "-") {
      object.shape = meshShape(s, env[k], "env_mesh_names");
      object.origin = "property env_mesh_names";
    }
    ++k;
  }
  if (k < env.size())
    throw std::invalid_argument("property env_mesh_names: " + std::to_string(env.size()) +
                                " meshes for " + std::to_string(k) + " environment objects of the scene");

  const std::vector<std::size_t> macro = linkIndices(s.macro_link_list, "macro_link_list");
  const std::vector<std::size_t> micro = linkIndices(s.micro_link_list, "micro_link_list");
  for (const auto& [list, group, property] : {std::tuple{&macro, "macro", "macro_link_list"},
                                              std::tuple{&micro, "micro", "micro_link_list"}}) {
    if (list->empty()) continue;
    if (scene.groupIndex(group) == SceneDescription::npos)
      throw std::invalid_argument(std::string("property ") + property + ": the scene has no group '" + group + "'");
    for (ObjectDescription& object : scene.objects)
      if (object.attached_to.robot_name == "isur" && contains(*list, object.attached_to.link_index))
        object.group = group;
  }
  for (const std::size_t link : macro)
    if (contains(micro, link))
      throw std::invalid_argument("property micro_link_list: link " + std::to_string(link) +
                                  " is also in macro_link_list; a link belongs to one group");
  const std::vector<std::size_t> ur5 = linkIndices(s.ur5_link_list, "UR5_link_list");
  if (!ur5.empty()) {
    std::erase_if(scene.objects, [&](const ObjectDescription& o) {
      return o.attached_to.robot_name == "ur5" && !contains(ur5, o.attached_to.link_index);
    });
    // The declared contacts of the objects that list left out go with them.
    for (auto* contacts : {&scene.allowed_contacts, &scene.primitive_contacts})
      std::erase_if(*contacts, [&](const auto& pair) {
        return scene.objectIndex(pair.first) == SceneDescription::npos ||
               scene.objectIndex(pair.second) == SceneDescription::npos;
      });
  }

  if (!(s.phantom_pose == KDL::Frame::Identity())) {
    const auto phantom = std::find_if(scene.objects.begin(), scene.objects.end(),
                                      [](const ObjectDescription& o) { return o.name == "phantom"; });
    if (phantom == scene.objects.end())
      throw std::invalid_argument("property phantom_pose: the scene has no object 'phantom' to place");
    phantom->offset = s.phantom_pose * phantom->offset;
  }
  for (planning::RobotPlacement& robot : scene.robots) {
    // Each tool takes the frame of the pose of q it serves (a robot taking both poses, Algorithm
    // 5.1: each of its tools its own).
    for (std::size_t t = 0; t < robot.tool_indices.size(); ++t) {
      const KDL::Frame& tool = robot.tool_indices[t] == 0 ? s.first_tool_frame : s.second_tool_frame;
      if (!(tool == KDL::Frame::Identity())) robot.setToolFrame(t, tool);
    }
  }
  if (s.min_collision_distance >= 0.0) scene.min_collision_distance = s.min_collision_distance;
  try {
    scene.validate();
  } catch (const std::exception& error) {
    throw std::invalid_argument(std::string("the scene after the property overrides: ") + error.what());
  }
  return scene;
}

PlanningSceneComponent::PlanningSceneComponent(std::string name, std::string doc)
    : Component(std::move(name), core::Role::Calculation, std::move(doc)) {
  addProperty(models_folder_);
  addProperty(scene_file_);
  addProperty(isur_mesh_names_);
  addProperty(ur5_mesh_names_);
  addProperty(env_mesh_names_);
  addProperty(macro_link_list_);
  addProperty(micro_link_list_);
  addProperty(ur5_link_list_);
  addProperty(mesh_scale_.range(1e-9, 1e3));
  addProperty(min_collision_distance_.range(-1.0, 1.0));
  addProperty(phantom_pose_);
  addProperty(first_tool_frame_);
  addProperty(second_tool_frame_);
}

PlanningSceneSettings PlanningSceneComponent::settings() const {
  return {.models_folder = models_folder_(),
          .scene_file = scene_file_(),
          .isur_mesh_names = isur_mesh_names_(),
          .ur5_mesh_names = ur5_mesh_names_(),
          .env_mesh_names = env_mesh_names_(),
          .macro_link_list = macro_link_list_(),
          .micro_link_list = micro_link_list_(),
          .ur5_link_list = ur5_link_list_(),
          .mesh_scale = mesh_scale_(),
          .min_collision_distance = min_collision_distance_(),
          .phantom_pose = phantom_pose_(),
          .first_tool_frame = first_tool_frame_(),
          .second_tool_frame = second_tool_frame_()};
}

std::unique_ptr<planning::StateValidator> PlanningSceneComponent::buildValidator() const {
  planning::SceneDescription scene = buildPlanningScene(settings());
  planning::RobotModels models;
  try {
    models = planning::makeRobotModels(scene);
  } catch (const std::exception& error) {
    throw std::invalid_argument(std::string("property scene_file: ") + error.what());
  }
  try {
    return std::make_unique<planning::StateValidator>(std::move(scene), std::move(models));
  } catch (const std::exception& error) {
    throw std::invalid_argument(std::string("property scene_file: ") + error.what());
  }
}

}  // namespace cobra::components
