#pragma once
// A robot cobra studio draws from the DH chain of its kinematics solver component, for the robots
// no planning scene models (run.studio.robots.NAME = { "Comp.joints", kinematics = "Kin" }: the
// Puma 260). The link frames are the chain's (kinematics::SerialChainModel::linkFrames, the DH
// frames 0..n and the tool, in the world), the drawn shapes cylinders along the chain's legs:
// each DH row's offset d along z_{i-1} and length a along x_i, fixed in frame i, a housing on
// each joint's axis and a leg from the last DH frame to the tool. Shapes are for drawing only
// (their radius follows the robot's reach); the robot's collision geometry is the scene's.

#include <memory>
#include <string>
#include <vector>

#include "cobra/core/introspection.hpp"
#include "cobra/kinematics/serial_chain.hpp"
#include "cobra/planning/geometry.hpp"

namespace cobra::studio {

// The chain of the KinematicsSolver component `component` as it computes its `cartPose`:
// `base_frame` · DH chain of `robot` ("puma260", "ur5" or "dh" with its `dh_table`) · `tool_frame`.
// @throws std::runtime_error "WHERE: USE: ..." for an unknown component, one that is not a
//         kinematics solver (no property robot/base_frame/tool_frame) or an unknown robot.
kinematics::SerialChainModel kinematicsChain(const core::ComponentRegistry& registry, const std::string& component,
                                             const std::string& where, const std::string& use);

// The shapes drawn for `chain`, attached to the link frames of robot `robot` (group `robot`
// for the legs, `robot` + ".joints" for the joint housings), in the link frames [m].
std::vector<planning::ObjectDescription> chainShapes(const std::string& robot, const kinematics::SerialChainModel& chain);

}  // namespace cobra::studio
