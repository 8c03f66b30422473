#pragma once
// Record types of the dds tests (core/record.hpp): one that mirrors geometry_msgs/Vector3, and a
// probe reading with every kind of field (numbers, a bool between doubles for alignment, a
// string, a sequence, built-in types carried by their ROS 2 messages, a nested record).
#include <string>
#include <tuple>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/core/event.hpp"
#include "cobra/core/record.hpp"

namespace cobra::dds::test {

struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;
};

struct Gains {
  double stiffness = 0.0;  // N/m
  int samples = 0;
  bool enabled = false;
};

struct ProbeReading {
  bool valid = false;
  double depth = 0.0;  // m
  std::string label;
  KDL::Frame pose;
  int count = 0;
  Gains gains;
  std::vector<double> profile;
  core::Event last;
  KDL::Twist motion;
};

}  // namespace cobra::dds::test

template <>
struct cobra::core::DataTypeTraits<cobra::dds::test::Vec3> : cobra::core::RecordTraits<cobra::dds::test::Vec3> {
  using T = cobra::dds::test::Vec3;
  static constexpr std::string_view name = "probe_msgs.Vec3";
  static constexpr auto fields = std::tuple{field("x", &T::x, "m"), field("y", &T::y, "m"), field("z", &T::z, "m")};
};

template <>
struct cobra::core::DataTypeTraits<cobra::dds::test::Gains> : cobra::core::RecordTraits<cobra::dds::test::Gains> {
  using T = cobra::dds::test::Gains;
  static constexpr std::string_view name = "probe_msgs.Gains";
  static constexpr auto fields = std::tuple{field("stiffness", &T::stiffness, "N/m", "contact stiffness"),
                                            field("samples", &T::samples, "1"), field("enabled", &T::enabled)};
};

template <>
struct cobra::core::DataTypeTraits<cobra::dds::test::ProbeReading>
    : cobra::core::RecordTraits<cobra::dds::test::ProbeReading> {
  using T = cobra::dds::test::ProbeReading;
  static constexpr std::string_view name = "probe_msgs.ProbeReading";
  static constexpr auto fields =
      std::tuple{field("valid", &T::valid), field("depth", &T::depth, "m", "depth of the image below the probe"),
                 field("label", &T::label), field("pose", &T::pose, "m, quaternion"), field("count", &T::count, "1"),
                 field("gains", &T::gains), field("profile", &T::profile, "m"), field("last", &T::last),
                 field("motion", &T::motion, "m/s, rad/s")};
};

namespace cobra::dds::test {

/// A reading with every field set (`seed` varies them).
inline ProbeReading probeReading(int seed = 1) {
  ProbeReading r;
  r.valid = seed % 2 == 1;
  r.depth = 0.05 * seed;
  r.label = "liver segment " + std::to_string(seed) + ", a label longer than the small-string buffer";
  r.pose = KDL::Frame(KDL::Rotation::RPY(0.1 * seed, -0.2, 0.3), KDL::Vector(0.1, 0.2 * seed, -0.3));
  r.count = -7 * seed;
  r.gains = {250.0 * seed, 3 * seed, seed % 2 == 0};
  r.profile = std::vector<double>(static_cast<std::size_t>(seed % 5 + 1), 0.25 * seed);
  r.last.name = "e_contact";
  r.last.source = "probe";
  r.last.stamp = std::chrono::nanoseconds(1000 * seed);
  r.motion = KDL::Twist(KDL::Vector(0.01, 0.02, 0.03 * seed), KDL::Vector(-0.1, 0.2, 0.3));
  return r;
}

/// Equal field by field; the pose's rotation within 1e-12 (it travels as a quaternion).
inline bool same(const ProbeReading& a, const ProbeReading& b) {
  return a.valid == b.valid && a.depth == b.depth && a.label == b.label && KDL::Equal(a.pose, b.pose, 1e-12) &&
         a.count == b.count && a.gains.stiffness == b.gains.stiffness && a.gains.samples == b.gains.samples &&
         a.gains.enabled == b.gains.enabled && a.profile == b.profile && a.last.name == b.last.name &&
         a.last.source == b.last.source && a.last.stamp == b.last.stamp && a.motion == b.motion;
}

}  // namespace cobra::dds::test
