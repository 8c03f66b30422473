#pragma once
/// @file
/// TGL's `MultiAxisPath` as a port type (the Motion Planner's `plannedPath`, thesis §4.5.1-4.5.2),
/// and the encoding of multi-arm Cartesian paths in it.
///
/// Encoding of a Cartesian path for `arms` arms: every waypoint holds 7 values per arm, arm after
/// arm: x, y, z (m) then a unit quaternion qx, qy, qz, qw of the tool orientation, in the base
/// frame. The same order as the text form of a KDL.Frame.

#include <string>
#include <string_view>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/core/data_type.hpp"
#include "cobra/trajectory/multi_axis.hpp"

namespace cobra::core {

template <>
struct DataTypeTraits<trajectory::MultiAxisPath> {
  static constexpr std::string_view name = "TGL.MultiAxisPath";
  static constexpr DataKind kind = DataKind::Pure;
  static constexpr std::string_view format = "a list of waypoints, each a list of axis values: [[0, 0.1], [0.2, 0.3]]";
  static std::string print(const trajectory::MultiAxisPath& value);
  static bool parse(std::string_view text, trajectory::MultiAxisPath& out);
};

}  // namespace cobra::core

namespace cobra::components {

/// Values per arm in a Cartesian path waypoint (x, y, z, qx, qy, qz, qw).
inline constexpr std::size_t kValuesPerArm = 7;

/// Writes `pose` as one arm's 7 values (x, y, z [m], qx, qy, qz, qw) at `values[0..6]`, in place:
/// allocates nothing (a real-time path refilled each time it is sent). `values` holds at least 7.
void encodeCartesianPose(const KDL::Frame& pose, double* values) noexcept;

/// `waypoints[k][arm]` in the encoding above.
trajectory::MultiAxisPath encodeCartesianPath(const std::vector<std::vector<KDL::Frame>>& waypoints);

/// The frames of `path` for `arms` arms. Quaternions are normalised.
/// @throws std::invalid_argument naming the waypoint when it does not hold 7 * arms finite values
///         or a quaternion has (nearly) zero norm.
std::vector<std::vector<KDL::Frame>> decodeCartesianPath(const trajectory::MultiAxisPath& path, std::size_t arms);

}  // namespace cobra::components
