#include "cobra/components/planning/motion_planner_component.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "cobra/core/activity.hpp"

namespace cobra::components {

namespace {

/// Bounds from two 3-value properties. @throws std::invalid_argument naming them.
planning::PositionBounds bounds(const std::vector<double>& low, const std::vector<double>& high, const char* name) {
  if (low.size() != 3 || high.size() != 3)
    throw std::invalid_argument(std::string("properties ") + name + "_low/_high need 3 values each (x, y, z in m)");
  planning::PositionBounds b;
  for (std::size_t i = 0; i < 3; ++i) {
    b.low[i] = low[i];
    b.high[i] = high[i];
    if (!(low[i] < high[i]))
      throw std::invalid_argument(std::string("properties ") + name + "_low/_high: low must be < high on every axis");
  }
  return b;
}

}  // namespace

MotionPlannerComponent::MotionPlannerComponent(std::string name)
    : PlanningSceneComponent(std::move(name),
                             "Motion planner (thesis §4.5.1): collision-free paths for the needle and the probe, OMPL "
                             "in the robots' joint space with FCL checks") {
  addProperty(planner_);
  addProperty(time_limit_.range(1e-3, 3600.0));
  addProperty(max_validity_checks_.range(0, 2000000000));
  addProperty(seed_.range(1, 2147483647));
  addProperty(first_low_);
  addProperty(first_high_);
  addProperty(second_low_);
  addProperty(second_high_);
  addProperty(edge_resolution_.range(1e-6, 1.0));
  addProperty(max_vel_.range(1e-6, 10.0));
  addProperty(max_ang_vel_.range(1e-6, 100.0));
  addProperty(time_acc_.range(1e-6, 10.0));
  addProperty(query_log_);
  addProperty(clearance_period_.range(0.0, 10.0));
  addEventPort(isur_meas_);
  addEventPort(ur5_meas_);
  addPort(isur_joints_);
  addPort(ur5_joints_);
  addPort(allowed_distance_);
  addPort(primitive_distance_);
  addPort(pair_distances_);
  addPort(goal_);
  addPort(path_out_);
  addPort(min_distance_);
  addOperation("askPlan", &MotionPlannerComponent::askPlan, this,
               "plans from the measured poses to goalPoses in this component's next step; answers e_plan_done "
               "(path on plannedPath) or e_plan_failed (reason: lastPlanResult)",
               core::ExecutionThread::Client);
  addOperation("checkDistancePoses", &MotionPlannerComponent::checkDistancePoses, this,
               "minimum distance between the checked groups for these needle and probe poses (NaN: unreachable)")
      .arg("ee1_pose", "m", "needle tip pose, world")
      .arg("ee2_pose", "m", "probe tip pose, world");
  addOperation("lastPlanResult", std::function<std::string()>([this] { return last_result_; }),
               "outcome of the last askPlan: 'solved: ...' or why it failed");
  addOperation("clearanceThreshold", std::function<double()>([this] {
                 return validator_ ? validator_->scene().min_collision_distance
                                   : std::numeric_limits<double>::quiet_NaN();
               }),
               "m: the clearance every planned state keeps outside the allowed contacts (NaN before configure)");
  addOperation("clearancePairs", std::function<std::string()>([this] {
                 std::string names;
                 if (validator_)
                   for (const std::string& pair : validator_->clearancePairs()) names += (names.empty() ? "" : ",") + pair;
                 return names;
               }),
               "the pairs of groups pairDistances gives, in its order, comma-separated (\"macro/ur5,ur5/environment\"; "
               "empty before configure)");
}

MotionPlannerComponent::~MotionPlannerComponent() = default;

bool MotionPlannerComponent::configureHook() {
  const std::vector<std::string>& names = planning::plannerNames();
  if (std::find(names.begin(), names.end(), planner_()) == names.end()) {
    std::string list;
    for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
    return refuse("property planner is '" + planner_() + "': use " + list);
  }
  planning::PlannerOptions options;
  try {
    options.first_bounds = bounds(first_low_(), first_high_(), "first_bounds");
    options.second_bounds = bounds(second_low_(), second_high_(), "second_bounds");
    validator_ = buildValidator();
  } catch (const std::invalid_argument& error) {
    return refuse(error.what());
  }
  options.planner = planner_();
  options.time_limit = time_limit_();
  options.max_validity_checks = static_cast<std::size_t>(max_validity_checks_());
  options.seed = static_cast<std::uint32_t>(seed_());
  options.edge_resolution = edge_resolution_();
  options.max_linear_velocity = max_vel_();
  options.max_angular_velocity = max_ang_vel_();
  options.blend_time = time_acc_();
  options.tool_names = {"needle", "probe"};
  planner_impl_ = std::make_unique<planning::MotionPlanner>(*validator_, options);
  joints_.assign(validator_->hasJointSpace() ? validator_->jointCount() : 0, 0.0);
  clearance_joints_.clear();
  clearance_joints_.reserve(joints_.size());  // updateHook copies joints_ here without allocating
  pair_values_.assign(validator_->clearancePairs().size(), std::numeric_limits<double>::quiet_NaN());
  pair_distances_.setDataSample(pair_values_);  // a write of that size allocates nothing
  have_isur_ = have_ur5_ = have_goal_ = have_isur_joints_ = have_ur5_joints_ = false;
  last_result_.clear();
  return true;
}

bool MotionPlannerComponent::startHook() {
  if (activity().period().count() > 0)
    return refuse("planning runs in updateHook for up to time_limit s: give this component a non-periodic, "
                  "non-real-time activity (EventActivity with Scheduler::Other, or period 0 on a LockstepClock)");
  plan_request_.clear();
  last_clearance_ns_ = -1;
  return true;
}

void MotionPlannerComponent::cleanupHook() {
  planner_impl_.reset();
  validator_.reset();
}

void MotionPlannerComponent::askPlan() {
  plan_request_.ask(activity());
}

double MotionPlannerComponent::checkDistancePoses(KDL::Frame first, KDL::Frame second) {
  if (!validator_) return std::numeric_limits<double>::quiet_NaN();
  return validator_->minimumDistance({first, second});
}

namespace {
/// "(x, y, z m; r, p, y rad)" of one frame, for the messages of a failed plan.
std::string describe(const KDL::Frame& f) {
  double r = 0, p = 0, y = 0;
  f.M.GetRPY(r, p, y);
  char text[160];
  std::snprintf(text, sizeof text, "(%.4f, %.4f, %.4f m; %.4f, %.4f, %.4f rad)", f.p.x(), f.p.y(), f.p.z(), r, p, y);
  return text;
}
std::string describe(const planning::DualPose& q) {
  return "first " + describe(q.first) + " second " + describe(q.second);
}
}  // namespace

void MotionPlannerComponent::fail(const std::string& reason) {
  last_result_ = reason;
  std::fprintf(stderr, "[cobra] MotionPlanner '%s': plan failed: %s\n", name().c_str(), reason.c_str());
  emitEvent("e_plan_failed");
}

bool MotionPlannerComponent::measuredJoints() {
  if (joints_.empty()) return false;
  // The joints of every robot of the scene, and only those: the suturing scene has the I-SUR
  // alone, so UR5MeasJoints stays unconnected there.
  const planning::SceneDescription& scene = validator_->scene();
  for (std::size_t r = 0; r < scene.robots.size(); ++r) {
    const bool isur = scene.robots[r].name == "isur";
    if (!isur && scene.robots[r].name != "ur5") return false;
    const KDL::JntArray& q = isur ? isur_q_ : ur5_q_;
    if (!(isur ? have_isur_joints_ : have_ur5_joints_) || q.rows() != validator_->model(r).jointCount()) return false;
    for (unsigned j = 0; j < q.rows(); ++j) joints_[validator_->jointOffset(r) + j] = q.data(j);
  }
  return true;
}

bool MotionPlannerComponent::reusePath(const planning::JointState&, const planning::DualPose&,
                                       const planning::DualPose&, std::size_t, planning::PlanResult&) {
  return false;
}

bool MotionPlannerComponent::latestJoints(planning::JointState& q, std::string& why) {
  have_isur_joints_ = have_isur_joints_ || isur_joints_.read(isur_q_) != core::FlowStatus::NoData;
  have_ur5_joints_ = have_ur5_joints_ || ur5_joints_.read(ur5_q_) != core::FlowStatus::NoData;
  if (!validator_ || !measuredJoints()) {
    why = validator_ ? "ports isurMeasJoints/UR5MeasJoints: " + expectedJoints() : "not configured";
    return false;
  }
  q = joints_;
  return true;
}

std::string MotionPlannerComponent::expectedJoints() const {
  const planning::SceneDescription& scene = validator_->scene();
  std::string expected, got;
  for (std::size_t r = 0; r < scene.robots.size(); ++r) {
    const bool isur = scene.robots[r].name == "isur";
    const bool have = isur ? have_isur_joints_ : have_ur5_joints_;
    const std::string port = isur ? "isurMeasJoints" : "UR5MeasJoints";
    expected += std::string(expected.empty() ? "" : ", ") + port + " " +
                std::to_string(validator_->model(r).jointCount()) + " joints";
    got += std::string(got.empty() ? "" : ", ") +
           (have ? std::to_string((isur ? isur_q_ : ur5_q_).rows()) : std::string("no data"));
  }
  return "the scene's robots need " + expected + " (got " + got + ")";
}

void MotionPlannerComponent::updateHook() {
  // A new goal is taken as it arrives (readNew: no copy of the old one each step).
  trajectory::MultiAxisPath goal;
  if (goal_.readNew(goal) == core::FlowStatus::NewData) {
    try {
      readGoal(goal);
      have_goal_ = true;
    } catch (const std::invalid_argument& error) {
      have_goal_ = false;
      last_result_ = std::string("port goalPoses: ") + error.what();
    }
  }
  const bool plan_now = plan_request_.take();
  // The measured state's clearance: a monitoring figure, measured at most every clearance_period
  // and only while a port of it is connected (FCL distances of every checked pair: the most
  // expensive thing this component does per step).
  const std::int64_t now_ns = now().count();
  // Earlier than the last measurement: run time began again. On the wall clock it begins at the
  // executor's first tick, and this own-pace planner may have measured while the deployment was
  // loading, on the time of an earlier run; waiting for that time again left the clearance
  // unmeasured for as long as the earlier run had lasted.
  const bool clearance_due = last_clearance_ns_ < 0 || now_ns < last_clearance_ns_ ||
                             now_ns - last_clearance_ns_ >= static_cast<std::int64_t>(clearance_period_() * 1e9);
  // Whether a port of it is connected is asked (a lock per port) once per clearance_period too:
  // a planner nobody reads the clearance of (the probe's) would otherwise ask every step.
  const bool clearance_wanted =
      clearance_due && (min_distance_.connected() || allowed_distance_.connected() || primitive_distance_.connected() ||
                        pair_distances_.connected());
  if (clearance_due && !clearance_wanted) last_clearance_ns_ = now_ns;
  // The measured pose ports trigger this component at the robots' rate; their latest samples
  // are read only when a measurement or a plan uses them (the connections keep the latest).
  if (!plan_now && !clearance_wanted) return;
  const core::FlowStatus isur = isur_meas_.read(measured_.first);
  const core::FlowStatus ur5 = ur5_meas_.read(measured_.second);
  have_isur_ = have_isur_ || isur != core::FlowStatus::NoData;
  have_ur5_ = have_ur5_ || ur5 != core::FlowStatus::NoData;
  const core::FlowStatus isur_joints = isur_joints_.read(isur_q_);
  const core::FlowStatus ur5_joints = ur5_joints_.read(ur5_q_);
  have_isur_joints_ = have_isur_joints_ || isur_joints != core::FlowStatus::NoData;
  have_ur5_joints_ = have_ur5_joints_ || ur5_joints != core::FlowStatus::NoData;
  // New since the last read: since the last measurement, when no plan read them in between.
  const bool measured_changed =
      have_isur_ && have_ur5_ && (isur == core::FlowStatus::NewData || ur5 == core::FlowStatus::NewData);
  if (measured_changed && clearance_wanted) {
    last_clearance_ns_ = now_ns;
    if (measuredJoints()) {
      if (joints_ != clearance_joints_) {  // the same joints: the same distances, not measured again
        clearance_ = validator_->distancesAt(joints_, pair_values_);  // one FK for both
        clearance_joints_ = joints_;
      }
    } else {
      clearance_ = validator_->distancesAt(measured_, pair_values_);
    }
    pair_distances_.write(pair_values_);
    min_distance_.write(clearance_.clearance);
    allowed_distance_.write(clearance_.allowed_contact);
    primitive_distance_.write(clearance_.primitive_contact);
  }
  if (plan_now) plan();
}

void MotionPlannerComponent::logQuery(const planning::DualPose& goal, const planning::PlanResult& result) const {
  if (query_log_().empty()) return;
  std::FILE* file = std::fopen(query_log_().c_str(), "a");
  if (file == nullptr) {
    std::fprintf(stderr, "[cobra] MotionPlanner '%s': property query_log: cannot append to '%s'\n", name().c_str(),
                 query_log_().c_str());
    return;
  }
  std::fprintf(file, "start");
  for (const double q : joints_) std::fprintf(file, " %.17g", q);
  std::fprintf(file, " goal");
  for (const KDL::Frame* f : {&goal.first, &goal.second}) {
    double x = 0, y = 0, z = 0, w = 0;
    f->M.GetQuaternion(x, y, z, w);
    for (const double v : {f->p.x(), f->p.y(), f->p.z(), x, y, z, w}) std::fprintf(file, " %.17g", v);
  }
  std::fprintf(file, " # %s: %s\n", name().c_str(), planning::toString(result.status));
  std::fclose(file);
}

void MotionPlannerComponent::readGoal(const trajectory::MultiAxisPath& goal) {
  const std::size_t pairs = goal.axisCount() / (2 * kValuesPerArm);
  if (goal.empty() || goal.axisCount() % (2 * kValuesPerArm) != 0 || (pairs != 1 && pairs % 2 != 0))
    throw std::invalid_argument(
        "a waypoint holds " + std::to_string(goal.axisCount()) +
        " values; give 14 per goal alternative (the two goal poses) or 28 + 28 per motion to make room for (the "
        "goal, where the straight motion after it goes, then each later motion's start and end pair)");
  const std::vector<std::vector<KDL::Frame>> frames = decodeCartesianPath(goal, 2 * pairs);
  alternatives_.clear();
  for (const std::vector<KDL::Frame>& f : frames) {
    GoalAlternative a;
    a.goal = {f[0], f[1]};
    if (pairs > 1) {
      a.follow_on = {f[2], f[3]};
      a.has_follow_on = !KDL::Equal(f[0], f[2], 0.0) || !KDL::Equal(f[1], f[3], 0.0);
    }
    for (std::size_t p = 2; p + 1 < pairs; p += 2)
      a.room.push_back({{f[2 * p], f[2 * p + 1]}, {f[2 * p + 2], f[2 * p + 3]}});
    alternatives_.push_back(std::move(a));
  }
}

planning::PlanResult MotionPlannerComponent::planAlternative(const GoalAlternative& a, std::size_t index,
                                                            bool from_joints, bool checked_first) {
  // The motion primitive after the goal, which the goal joints must allow (MotionPlanner::planPath).
  const std::optional<planning::DualPose> follow_on =
      a.has_follow_on ? std::optional<planning::DualPose>(a.follow_on) : std::nullopt;
  if (checked_first) {
    // The cheap checks before the search: the goal state and the motions it must leave room for.
    planning::PlanResult checked = planner_impl_->checkGoal(joints_, a.goal, follow_on);
    for (std::size_t k = 0; k < a.room.size() && checked.solved(); ++k)
      checked = planner_impl_->checkMotion(joints_, a.room[k].first, a.room[k].second);
    if (!checked.solved()) return checked;
  }
  planning::PlanResult result;
  bool follow_on_checked = false;  // planPath from joints checked it from where its path ends
  if (!(from_joints && reusePath(joints_, measured_, a.goal, index, result))) {
    result = from_joints ? planner_impl_->planPath(joints_, a.goal, follow_on) : planner_impl_->planPath(measured_, a.goal);
    follow_on_checked = from_joints;
    if (from_joints) logQuery(a.goal, result);
  }
  if (!result.solved()) {
    // The same query with the same seed would fail the same way: the next request explores anew.
    const std::uint32_t seed = planner_impl_->options().seed;
    planner_impl_->setSeed(seed == UINT32_MAX ? 1 : seed + 1);
    return result;
  }
  if (a.has_follow_on && !follow_on_checked) {
    // The motion primitive that follows this goal (a reused verified path, or one planned from
    // the tool poses): a goal whose next motion cannot be made fails now, before anything moves.
    const planning::PlanResult next =
        planner_impl_->checkFollowOn(result.joint_waypoints.back(), result.waypoints.back(), a.follow_on);
    if (!next.solved()) return next;
  }
  return result;
}

void MotionPlannerComponent::plan() {
  if (!have_isur_ || !have_ur5_)
    return fail(std::string("no measured pose on port ") + (have_isur_ ? "UR5MeasPose" : "isurMeasPose") +
                ": the start state is unknown");
  if (!have_goal_)
    return fail(last_result_.rfind("port goalPoses", 0) == 0 ? last_result_
                                                              : std::string("no goal on port goalPoses"));
  const bool from_joints = measuredJoints();
  if ((have_isur_joints_ || have_ur5_joints_) && !from_joints && !joints_.empty())
    return fail("ports isurMeasJoints/UR5MeasJoints: " + expectedJoints());
  const bool rooms = std::any_of(alternatives_.begin(), alternatives_.end(),
                                 [](const GoalAlternative& a) { return !a.room.empty(); });
  if (rooms && !from_joints)
    return fail("the goal asks for room for a later motion, which is checked from the measured joints: connect "
                "ports isurMeasJoints and UR5MeasJoints");
  // The first alternative that passes its checks and to which a path is found (the preferred
  // first: the state table's order). One alternative keeps the messages of a single goal.
  std::string refused;
  planning::PlanResult result;
  std::size_t chosen = 0;
  for (; chosen < alternatives_.size(); ++chosen) {
    const GoalAlternative& a = alternatives_[chosen];
    result = planAlternative(a, chosen, from_joints, from_joints && (alternatives_.size() > 1 || !a.room.empty()));
    if (result.solved()) break;
    const std::string why = std::string(planning::toString(result.status)) + ": " + result.message;
    if (alternatives_.size() == 1) return fail(why + "; from " + describe(measured_) + " to " + describe(a.goal));
    refused += std::string(refused.empty() ? "" : "; ") + "goal " + std::to_string(chosen + 1) + " of " +
               std::to_string(alternatives_.size()) + " " + describe(a.goal) + ": " + why;
  }
  if (chosen == alternatives_.size())
    return fail("none of the " + std::to_string(alternatives_.size()) + " goal alternatives can be taken from " +
                describe(measured_) + ": " + refused);
  std::vector<std::vector<KDL::Frame>> waypoints;
  waypoints.reserve(result.waypoints.size());
  for (const planning::DualPose& q : result.waypoints) waypoints.push_back({q.first, q.second});
  path_out_.write(encodeCartesianPath(waypoints));
  last_result_ = "solved: " + result.message + " in " + std::to_string(result.planning_time) + " s, " +
                 std::to_string(result.validity_checks) + " validity checks";
  if (alternatives_.size() > 1)
    last_result_ += "; goal " + std::to_string(chosen + 1) + " of " + std::to_string(alternatives_.size()) +
                    (refused.empty() ? "" : " (" + refused + ")");
  emitEvent("e_plan_done");
}

}  // namespace cobra::components
