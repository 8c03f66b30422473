#include "cobra/dds/conversions.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

namespace cobra::dds {
namespace {
/// A received string up to its first '\0': what the sender could have meant, since Fast CDR
/// writes a string as a C string (a peer may still send bytes after a '\0').
std::string_view cString(const std::string& text) { return {text.c_str()}; }
}  // namespace

void toMsg(double value, std_msgs::msg::Float64& msg) { msg.data(value); }
void fromMsg(const std_msgs::msg::Float64& msg, double& value) { value = msg.data(); }
void toMsg(int value, std_msgs::msg::Int32& msg) { msg.data(value); }
void fromMsg(const std_msgs::msg::Int32& msg, int& value) { value = msg.data(); }
void toMsg(bool value, std_msgs::msg::Bool& msg) { msg.data(value); }
void fromMsg(const std_msgs::msg::Bool& msg, bool& value) { value = msg.data(); }
void toMsg(const std::string& value, std_msgs::msg::String& msg) { msg.data() = value; }
void fromMsg(const std_msgs::msg::String& msg, std::string& value) { value.assign(cString(msg.data())); }

void toMsg(const std::vector<double>& value, std_msgs::msg::Float64MultiArray& msg) {
  msg.layout().dim().clear();
  msg.layout().data_offset(0);
  msg.data() = value;
}
void fromMsg(const std_msgs::msg::Float64MultiArray& msg, std::vector<double>& value) { value = msg.data(); }

void toMsg(const KDL::Vector& value, geometry_msgs::msg::Vector3& msg) {
  msg.x(value.x());
  msg.y(value.y());
  msg.z(value.z());
}
void fromMsg(const geometry_msgs::msg::Vector3& msg, KDL::Vector& value) { value = KDL::Vector(msg.x(), msg.y(), msg.z()); }

void toMsg(const KDL::Rotation& value, geometry_msgs::msg::Quaternion& msg) {
  double x = 0, y = 0, z = 0, w = 1;
  value.GetQuaternion(x, y, z, w);
  msg.x(x);
  msg.y(y);
  msg.z(z);
  msg.w(w);
}
void fromMsg(const geometry_msgs::msg::Quaternion& msg, KDL::Rotation& value) {
  // Scaled by its largest component first: squaring components of 1e-160 (or 1e160) underflows
  // (overflows), and the "unit" quaternion would not be one (the record fuzzer found it).
  const double largest = std::max({std::abs(msg.x()), std::abs(msg.y()), std::abs(msg.z()), std::abs(msg.w())});
  const bool finite = std::isfinite(msg.x()) && std::isfinite(msg.y()) && std::isfinite(msg.z()) && std::isfinite(msg.w());
  if (!finite || !(largest > 0.0)) {
    value = KDL::Rotation::Identity();
    return;
  }
  const double x = msg.x() / largest, y = msg.y() / largest, z = msg.z() / largest, w = msg.w() / largest;
  const double norm = std::sqrt(x * x + y * y + z * z + w * w);  // in [1, 2]
  value = KDL::Rotation::Quaternion(x / norm, y / norm, z / norm, w / norm);
}

void toMsg(const KDL::Frame& value, geometry_msgs::msg::Pose& msg) {
  msg.position().x(value.p.x());
  msg.position().y(value.p.y());
  msg.position().z(value.p.z());
  toMsg(value.M, msg.orientation());
}
void fromMsg(const geometry_msgs::msg::Pose& msg, KDL::Frame& value) {
  value.p = KDL::Vector(msg.position().x(), msg.position().y(), msg.position().z());
  fromMsg(msg.orientation(), value.M);
}

void toMsg(const KDL::Twist& value, geometry_msgs::msg::Twist& msg) {
  toMsg(value.vel, msg.linear());
  toMsg(value.rot, msg.angular());
}
void fromMsg(const geometry_msgs::msg::Twist& msg, KDL::Twist& value) {
  fromMsg(msg.linear(), value.vel);
  fromMsg(msg.angular(), value.rot);
}

void toMsg(const KDL::Wrench& value, geometry_msgs::msg::Wrench& msg) {
  toMsg(value.force, msg.force());
  toMsg(value.torque, msg.torque());
}
void fromMsg(const geometry_msgs::msg::Wrench& msg, KDL::Wrench& value) {
  fromMsg(msg.force(), value.force);
  fromMsg(msg.torque(), value.torque);
}

void toMsg(const KDL::JntArray& value, cobra_msgs::msg::JntArray& msg) {
  msg.data().assign(value.data.data(), value.data.data() + value.rows());
}
void fromMsg(const cobra_msgs::msg::JntArray& msg, KDL::JntArray& value) {
  if (value.rows() != msg.data().size()) value.resize(static_cast<unsigned int>(msg.data().size()));
  for (std::size_t i = 0; i < msg.data().size(); ++i) value(static_cast<unsigned int>(i)) = msg.data()[i];
}

void toMsg(const core::Event& value, cobra_msgs::msg::Event& msg) {
  msg.name().assign(value.name.view());
  msg.source().assign(value.source.view());
  msg.stamp_ns(value.stamp.count());
}
void fromMsg(const cobra_msgs::msg::Event& msg, core::Event& value) {
  value.name.assign(cString(msg.name()));
  value.source.assign(cString(msg.source()));
  value.stamp = std::chrono::nanoseconds(msg.stamp_ns());
}

void toMsg(const core::TaskState& value, cobra_msgs::msg::TaskState& msg) { msg.path().assign(value.path.view()); }
void fromMsg(const cobra_msgs::msg::TaskState& msg, core::TaskState& value) { value.path.assign(cString(msg.path())); }

}  // namespace cobra::dds
