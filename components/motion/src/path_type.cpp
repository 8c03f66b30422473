#include "cobra/components/motion/path_type.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace cobra::core {

std::string DataTypeTraits<trajectory::MultiAxisPath>::print(const trajectory::MultiAxisPath& value) {
  std::string text = "[";
  for (std::size_t k = 0; k < value.size(); ++k)
    text += (k == 0 ? "" : ", ") + DataTypeTraits<std::vector<double>>::print(value.waypoint(k));
  return text + "]";
}

bool DataTypeTraits<trajectory::MultiAxisPath>::parse(std::string_view text, trajectory::MultiAxisPath& out) {
  // Outer brackets around a comma-separated list of inner lists, each parsed as a vector<double>.
  const auto first = text.find_first_not_of(" \t\n");
  const auto last = text.find_last_not_of(" \t\n");
  if (first == std::string_view::npos || text[first] != '[' || text[last] != ']') return false;
  std::string_view inside = text.substr(first + 1, last - first - 1);
  trajectory::MultiAxisPath parsed;
  while (true) {
    const auto open = inside.find_first_not_of(" \t\n,");
    if (open == std::string_view::npos) break;
    if (inside[open] != '[') return false;
    const auto close = inside.find(']', open);
    if (close == std::string_view::npos) return false;
    std::vector<double> waypoint;
    if (!DataTypeTraits<std::vector<double>>::parse(inside.substr(open, close - open + 1), waypoint)) return false;
    parsed.addWaypoint(std::move(waypoint));
    inside.remove_prefix(close + 1);
    const auto next = inside.find_first_not_of(" \t\n");
    if (next != std::string_view::npos && inside[next] != ',') return false;
  }
  out = std::move(parsed);
  return true;
}

}  // namespace cobra::core

namespace cobra::components {

void encodeCartesianPose(const KDL::Frame& pose, double* values) noexcept {
  double qx = 0, qy = 0, qz = 0, qw = 1;
  pose.M.GetQuaternion(qx, qy, qz, qw);
  values[0] = pose.p.x();
  values[1] = pose.p.y();
  values[2] = pose.p.z();
  values[3] = qx;
  values[4] = qy;
  values[5] = qz;
  values[6] = qw;
}

trajectory::MultiAxisPath encodeCartesianPath(const std::vector<std::vector<KDL::Frame>>& waypoints) {
  trajectory::MultiAxisPath path;
  for (const auto& poses : waypoints) {
    std::vector<double> values;
    values.reserve(poses.size() * kValuesPerArm);
    for (const KDL::Frame& pose : poses) {
      values.resize(values.size() + kValuesPerArm);
      encodeCartesianPose(pose, values.data() + values.size() - kValuesPerArm);
    }
    path.addWaypoint(std::move(values));
  }
  return path;
}

std::vector<std::vector<KDL::Frame>> decodeCartesianPath(const trajectory::MultiAxisPath& path, std::size_t arms) {
  std::vector<std::vector<KDL::Frame>> frames;
  frames.reserve(path.size());
  for (std::size_t k = 0; k < path.size(); ++k) {
    const std::vector<double>& values = path.waypoint(k);
    if (values.size() != arms * kValuesPerArm) {
      std::ostringstream why;
      why << "waypoint " << k << " has " << values.size() << " values; " << arms << " arm(s) need "
          << arms * kValuesPerArm << " (x, y, z, qx, qy, qz, qw per arm)";
      throw std::invalid_argument(why.str());
    }
    std::vector<KDL::Frame> poses;
    for (std::size_t arm = 0; arm < arms; ++arm) {
      const double* v = values.data() + arm * kValuesPerArm;
      for (std::size_t i = 0; i < kValuesPerArm; ++i)
        if (!std::isfinite(v[i]))
          throw std::invalid_argument("waypoint " + std::to_string(k) + ", arm " + std::to_string(arm + 1) +
                                      ": value " + std::to_string(i) + " is not finite");
      const double norm = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
      if (norm < 1e-6)
        throw std::invalid_argument("waypoint " + std::to_string(k) + ", arm " + std::to_string(arm + 1) +
                                    ": the quaternion has zero norm; give a unit quaternion qx, qy, qz, qw");
      poses.emplace_back(KDL::Rotation::Quaternion(v[3] / norm, v[4] / norm, v[5] / norm, v[6] / norm),
                         KDL::Vector(v[0], v[1], v[2]));
    }
    frames.push_back(std::move(poses));
  }
  return frames;
}

}  // namespace cobra::components
