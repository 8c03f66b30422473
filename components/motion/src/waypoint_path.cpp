#include "cobra/components/motion/waypoint_path.hpp"

#include <cmath>

namespace cobra::components {

WaypointPath::WaypointPath(std::string name)
    : Component(std::move(name), core::Role::Calculation,
                "a fixed Cartesian path (property waypoints) sent from the tool's measured pose on askPath()") {
  addProperty(waypoints_);
  addProperty(relative_);
  addPort(meas_pose_);
  addPort(path_);
  addOperation("askPath", &WaypointPath::askPath, this,
               "writes path from the measured pose through the waypoints in the next step (e_path_sent, or "
               "e_no_data without a measured pose)",
               core::ExecutionThread::Client);
  addOperation("waypointCount", std::function<int()>([this] { return static_cast<int>(waypoints_().size() / kValuesPerArm); }),
               "number of poses in the waypoints property");
}

bool WaypointPath::configureHook() {
  const std::vector<double>& values = waypoints_();
  if (values.empty() || values.size() % kValuesPerArm != 0)
    return refuse("property waypoints has " + std::to_string(values.size()) +
                  " values; expected 7 per pose (x y z [m] qx qy qz qw), at least one pose");
  std::vector<std::vector<double>> waypoints(1, std::vector<double>(kValuesPerArm, 0.0));
  offsets_.clear();
  for (std::size_t k = 0; k < values.size(); k += kValuesPerArm) {
    const std::vector<double> pose(values.begin() + static_cast<std::ptrdiff_t>(k),
                                   values.begin() + static_cast<std::ptrdiff_t>(k + kValuesPerArm));
    double norm = 0.0;
    bool finite = true;
    for (std::size_t i = 0; i < kValuesPerArm; ++i) {
      finite = finite && std::isfinite(pose[i]);
      if (i >= 3) norm += pose[i] * pose[i];
    }
    if (!finite || norm < 1e-12)
      return refuse("property waypoints: pose " + std::to_string(k / kValuesPerArm + 1) +
                    " needs finite values and a non-zero quaternion");
    waypoints.push_back(pose);
    const double n = std::sqrt(norm);  // KDL's Quaternion expects a unit quaternion
    offsets_.emplace_back(KDL::Rotation::Quaternion(pose[3] / n, pose[4] / n, pose[5] / n, pose[6] / n),
                          KDL::Vector(pose[0], pose[1], pose[2]));
  }
  path_data_ = trajectory::MultiAxisPath(std::move(waypoints));
  path_.setDataSample(path_data_);
  have_measured_ = false;
  return true;
}

bool WaypointPath::startHook() {
  ask_path_.clear();
  return true;
}

void WaypointPath::askPath() { ask_path_.ask(activity()); }

void WaypointPath::updateHook() {
  if (meas_pose_.read(measured_) != core::FlowStatus::NoData) have_measured_ = true;
  if (!ask_path_.take()) return;
  if (!have_measured_) {
    emitEvent("e_no_data");
    return;
  }
  encodeCartesianPose(measured_, path_data_.waypoint(0).data());
  if (relative_())
    for (std::size_t k = 0; k < offsets_.size(); ++k)
      encodeCartesianPose(KDL::Frame(offsets_[k].M * measured_.M, measured_.p + offsets_[k].p),
                          path_data_.waypoint(k + 1).data());
  path_.write(path_data_);
  emitEvent("e_path_sent");
}

}  // namespace cobra::components
