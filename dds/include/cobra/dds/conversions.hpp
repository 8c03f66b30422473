#pragma once
/// @file
/// cobra's built-in port types as ROS 2 messages: which message carries each type on DDS and
/// the conversions both ways (the built-in codecs of codec.hpp use them). Units are SI on both
/// sides (m, rad, m/s, rad/s, N, N·m, ns). Records (core/record.hpp) need none: record_wire.hpp.
///
/// | cobra type       | DDS type (ROS 2 name)                       |
/// | ---------------- | ------------------------------------------- |
/// | double           | std_msgs::msg::dds_::Float64_               |
/// | int              | std_msgs::msg::dds_::Int32_                 |
/// | bool             | std_msgs::msg::dds_::Bool_                  |
/// | string           | std_msgs::msg::dds_::String_                |
/// | vector<double>   | std_msgs::msg::dds_::Float64MultiArray_ (no dimensions: a flat list) |
/// | KDL.Vector       | geometry_msgs::msg::dds_::Vector3_          |
/// | KDL.Rotation     | geometry_msgs::msg::dds_::Quaternion_       |
/// | KDL.Frame        | geometry_msgs::msg::dds_::Pose_             |
/// | KDL.Twist        | geometry_msgs::msg::dds_::Twist_            |
/// | KDL.Wrench       | geometry_msgs::msg::dds_::Wrench_           |
/// | KDL.JntArray     | cobra_msgs::msg::dds_::JntArray_            |
/// | Event            | cobra_msgs::msg::dds_::Event_               |
/// | TaskState        | cobra_msgs::msg::dds_::TaskState_           |
///
/// The conversions allocate only what a message's or value's sequences and strings need; they
/// run on the transport's threads, never on a component's.

#include <string>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/core/event.hpp"
#include "cobra_msgs/msg/EventPubSubTypes.h"
#include "cobra_msgs/msg/JntArrayPubSubTypes.h"
#include "cobra_msgs/msg/TaskStatePubSubTypes.h"
#include "geometry_msgs/msg/PosePubSubTypes.h"
#include "geometry_msgs/msg/QuaternionPubSubTypes.h"
#include "geometry_msgs/msg/TwistPubSubTypes.h"
#include "geometry_msgs/msg/Vector3PubSubTypes.h"
#include "geometry_msgs/msg/WrenchPubSubTypes.h"
#include "std_msgs/msg/BoolPubSubTypes.h"
#include "std_msgs/msg/Float64MultiArrayPubSubTypes.h"
#include "std_msgs/msg/Float64PubSubTypes.h"
#include "std_msgs/msg/Int32PubSubTypes.h"
#include "std_msgs/msg/StringPubSubTypes.h"

namespace cobra::dds {

void toMsg(double value, std_msgs::msg::Float64& msg);
void fromMsg(const std_msgs::msg::Float64& msg, double& value);
void toMsg(int value, std_msgs::msg::Int32& msg);
void fromMsg(const std_msgs::msg::Int32& msg, int& value);
void toMsg(bool value, std_msgs::msg::Bool& msg);
void fromMsg(const std_msgs::msg::Bool& msg, bool& value);
void toMsg(const std::string& value, std_msgs::msg::String& msg);
void fromMsg(const std_msgs::msg::String& msg, std::string& value);
/// A flat list: no layout dimensions, data_offset 0. Reading ignores the layout (takes `data`).
void toMsg(const std::vector<double>& value, std_msgs::msg::Float64MultiArray& msg);
void fromMsg(const std_msgs::msg::Float64MultiArray& msg, std::vector<double>& value);

void toMsg(const KDL::Vector& value, geometry_msgs::msg::Vector3& msg);
void fromMsg(const geometry_msgs::msg::Vector3& msg, KDL::Vector& value);
/// The rotation's unit quaternion (KDL's choice of sign: w >= 0).
void toMsg(const KDL::Rotation& value, geometry_msgs::msg::Quaternion& msg);
/// Normalises the quaternion first (also one of tiny or huge components); a zero (or not
/// finite) quaternion, as a message whose orientation was never set has, gives the identity.
void fromMsg(const geometry_msgs::msg::Quaternion& msg, KDL::Rotation& value);
/// Position in m, orientation as a unit quaternion.
void toMsg(const KDL::Frame& value, geometry_msgs::msg::Pose& msg);
void fromMsg(const geometry_msgs::msg::Pose& msg, KDL::Frame& value);
/// linear = KDL's vel (m/s), angular = KDL's rot (rad/s).
void toMsg(const KDL::Twist& value, geometry_msgs::msg::Twist& msg);
void fromMsg(const geometry_msgs::msg::Twist& msg, KDL::Twist& value);
/// force in N, torque in N·m.
void toMsg(const KDL::Wrench& value, geometry_msgs::msg::Wrench& msg);
void fromMsg(const geometry_msgs::msg::Wrench& msg, KDL::Wrench& value);
/// Joint values: rad for revolute, m for prismatic joints. Reading resizes `value` to the message.
void toMsg(const KDL::JntArray& value, cobra_msgs::msg::JntArray& msg);
void fromMsg(const cobra_msgs::msg::JntArray& msg, KDL::JntArray& value);
/// stamp in ns on the emitter's clock. Reading keeps the first 63 characters of name and source.
void toMsg(const core::Event& value, cobra_msgs::msg::Event& msg);
void fromMsg(const cobra_msgs::msg::Event& msg, core::Event& value);
/// Reading keeps the first 127 characters of the path.
void toMsg(const core::TaskState& value, cobra_msgs::msg::TaskState& msg);
void fromMsg(const cobra_msgs::msg::TaskState& msg, core::TaskState& value);

}  // namespace cobra::dds
