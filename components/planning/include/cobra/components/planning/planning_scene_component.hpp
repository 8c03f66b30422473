#pragma once
/// @file
/// The scene properties the Motion Planner and the State Validator share (thesis §4.5.1): where
/// the scene and the meshes are, the thesis' mesh name and link index lists as overrides of the
/// scene file, the collision threshold and the phantom pose; and the StateValidator built from
/// them at configure time with the real robot models (planning::makeRobotModels).

#include <memory>
#include <string>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/core/component.hpp"
#include "cobra/planning/scene.hpp"
#include "cobra/planning/state_validator.hpp"

namespace cobra::components {

/// What the scene properties say, as plain data (for buildPlanningScene and its tests).
struct PlanningSceneSettings {
  std::string models_folder;
  std::string scene_file;
  std::string isur_mesh_names;
  std::string ur5_mesh_names;
  std::string env_mesh_names;
  std::vector<double> macro_link_list;
  std::vector<double> micro_link_list;
  std::vector<double> ur5_link_list;
  double mesh_scale = 0.001;
  double min_collision_distance = -1.0;
  KDL::Frame phantom_pose = KDL::Frame::Identity();
  /// The frames the two poses of q give, each in the model frame of the robot tool that takes it
  /// (identity: as the scene says). E.g. an application whose needle frame has z along the needle,
  /// where the I-SUR model's needle is its tool's x axis: RotY(90°); a two-tool robot's second
  /// tool a stick's tip on its gripper.
  KDL::Frame first_tool_frame = KDL::Frame::Identity();
  KDL::Frame second_tool_frame = KDL::Frame::Identity();
};

/// The scene file with the overrides applied (see PlanningSceneComponent for their meaning).
/// Meshes named by the overrides are loaded once here to check them.
/// @throws std::invalid_argument "property NAME: ..." naming the property and the file/value.
planning::SceneDescription buildPlanningScene(const PlanningSceneSettings& settings);

/// Base of the planning components. Properties (thesis names):
/// - `models_folder` (path): folder of the scene file and meshes when given relative; "" = cwd.
/// - `scene_file` (path): cobra's scene file (cobra/planning/scene.hpp; e.g. an application's deployment/*.scene: robots, groups,
///   objects, checked pairs). Required.
/// - `isur_mesh_names`, `UR5_mesh_names` (blank- or comma-separated file names, `-` = keep): mesh
///   i replaces the scene's shapes on link i of that robot (mesh in the link frame, in
///   `mesh_scale` units). `env_mesh_names`: mesh k replaces the k-th object of group
///   `environment` (keeping its name and pose). Empty: the scene's shapes.
/// - `macro_link_list`, `micro_link_list` (I-SUR link indices): which group (macro / micro) the
///   objects on those links belong to; `UR5_link_list`: the UR5 links checked (objects on other
///   links are left out). Empty: as the scene says.
/// - `mesh_scale` (m per mesh unit, 0.001 for CAD in mm), `min_collision_distance` (m; < 0: the
///   scene's), `phantom_pose` (KDL.Frame, m: places the phantom frame, in which the scene's object
///   `phantom` is given, in the world; identity = as in the scene), `first_tool_frame` and
///   `second_tool_frame` (KDL.Frame, m: the frame each pose of q names, in the model frame of the
///   robot tool that takes it, also for a robot that takes both; non-identity values replace the
///   scene's frame of that tool).
/// The scene file stays the primary description (the thesis' lists are data the scene already
/// holds per object); the properties exist for the thesis' deployment files and override it.
class PlanningSceneComponent : public core::Component {
 public:
  /// The scene this component checks collisions in: the scene file with the properties'
  /// overrides (e.g. for cobra studio to draw the same geometry). @throws as buildPlanningScene.
  planning::SceneDescription sceneDescription() const { return buildPlanningScene(settings()); }

 protected:
  PlanningSceneComponent(std::string name, std::string doc);

  PlanningSceneSettings settings() const;
  /// buildPlanningScene + StateValidator with the real robot models.
  /// @throws std::invalid_argument naming the property at fault.
  std::unique_ptr<planning::StateValidator> buildValidator() const;

  core::Property<std::string> models_folder_{"models_folder", "", "path", "folder of the scene file and the meshes"};
  core::Property<std::string> scene_file_{"scene_file", "", "path",
                                          "scene file (robots, groups, objects, checks), relative to models_folder"};
  core::Property<std::string> isur_mesh_names_{"isur_mesh_names", "", "file names",
                                               "mesh per I-SUR link (overrides the scene; '-' keeps a link's shapes)"};
  core::Property<std::string> ur5_mesh_names_{"UR5_mesh_names", "", "file names",
                                              "mesh per UR5 link (overrides the scene; '-' keeps a link's shapes)"};
  core::Property<std::string> env_mesh_names_{"env_mesh_names", "", "file names",
                                              "mesh per environment object, in scene order ('-' keeps one)"};
  core::Property<std::vector<double>> macro_link_list_{"macro_link_list", {}, "1",
                                                       "I-SUR links in the macro group (empty: as the scene)"};
  core::Property<std::vector<double>> micro_link_list_{"micro_link_list", {}, "1",
                                                       "I-SUR links in the micro group (empty: as the scene)"};
  core::Property<std::vector<double>> ur5_link_list_{"UR5_link_list", {}, "1",
                                                     "UR5 links checked for collisions (empty: as the scene)"};
  core::Property<double> mesh_scale_{"mesh_scale", 0.001, "m", "size of one mesh file unit"};
  core::Property<double> min_collision_distance_{"min_collision_distance", -1.0, "m",
                                                 "distance every checked pair must exceed (< 0: the scene's)"};
  core::Property<KDL::Frame> first_tool_frame_{"first_tool_frame", KDL::Frame::Identity(), "m",
                                              "frame the first pose of q names, in the model frame of the tool that takes it"};
  core::Property<KDL::Frame> second_tool_frame_{"second_tool_frame", KDL::Frame::Identity(), "m",
                                               "frame the second pose of q names, in the model frame of the tool that takes it"};
  core::Property<KDL::Frame> phantom_pose_{"phantom_pose", KDL::Frame::Identity(), "m",
                                           "pose of the phantom frame in the world (identity: as in the scene)"};
};

}  // namespace cobra::components
