#include "cobra/components/puncturing/procedure_planner.hpp"

#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>

#include "cobra/components/puncturing/navigation_plan.hpp"
#include "cobra/puncturing/procedure.hpp"
#include "cobra/task/planned_walk.hpp"

namespace cobra::components {

PuncturingMotionPlanner::PuncturingMotionPlanner(std::string name) : MotionPlannerComponent(std::move(name)) {
  for (core::Property<std::string>* file : {&preoperative_file_, &cryo_plan_file_, &probe_plan_file_, &table_file_})
    addProperty(*file);
  addProperty(arm_);
  addProperty(plan_source_);
  addProperty(other_max_vel_.range(1e-6, 10.0));
  addProperty(other_max_ang_vel_.range(1e-6, 100.0));
  // Event ports: a registration or a plan arriving wakes a verification waiting for it.
  addEventPort(abdomen_frame_);
  addEventPort(plan_in_);
  addPort(refusal_);
  addOperation("verifyProcedure", std::function<void()>([this] { verify_request_.ask(activity()); }),
               "verifies every motion of the procedure for the plan and the registration in this component's next "
               "step, before anything moves; answers e_procedure_verified or e_procedure_refused (why: lastRefusal)",
               core::ExecutionThread::Client);
  addOperation("lastRefusal", std::function<std::string()>([this] { return last_refusal_; }),
               "why the last verifyProcedure refused the procedure: the needle, the task state and its table line, "
               "the datum and why ('' when it passed)");
  addOperation("lastVerification", std::function<std::string()>([this] { return last_verification_; }),
               "what the last verifyProcedure found");
}

bool PuncturingMotionPlanner::configureHook() {
  if (!MotionPlannerComponent::configureHook()) return false;
  if (arm_() != "needle" && arm_() != "probe") return refuse("property arm is '" + arm_() + "'; expected needle or probe");
  arm_index_ = arm_() == "needle" ? 0 : 1;
  const std::pair<const core::Property<std::string>*, const char*> files[] = {
      {&preoperative_file_, "preoperative_info_file"}, {&cryo_plan_file_, "cryo_plan_file"},
      {&probe_plan_file_, "US_pose_plan_file"}, {&table_file_, "state_table_file"}};
  const bool navigated = plan_source_() == "navigation";
  if (!navigated && plan_source_() != "files")
    return refuse("property plan_source is '" + plan_source_() + "'; expected files or navigation");
  for (const auto& [file, name] : files) {
    if ((*file)().empty() && (!navigated || file == &preoperative_file_ || file == &table_file_))
      return refuse(std::string("property ") + name + " is empty; give the path of its file");
  }
  plan_.reset();
  table_.reset();
  preoperative_.reset();
  navigation_ = {};
  try {
    if (navigated)
      preoperative_ = puncturing::parsePreoperative(puncturing::readText(preoperative_file_()), preoperative_file_());
    else
      plan_ = puncturing::loadPlan(preoperative_file_(), cryo_plan_file_(), probe_plan_file_());
    table_ = puncturing::parseStateTable(puncturing::readText(table_file_()), table_file_());
  } catch (const std::invalid_argument& e) {
    plan_.reset();
    table_.reset();
    preoperative_.reset();
    return refuse(e.what());
  }
  abdomen_ = navigated ? preoperative_->abdomen_in_task : plan_->preoperative.abdomen_in_task;
  last_refusal_.clear();
  last_verification_.clear();
  return true;
}

void PuncturingMotionPlanner::updateHook() {
  MotionPlannerComponent::updateHook();
  verify_pending_ = verify_request_.take() || verify_pending_;
  if (verify_pending_) verify();
}

namespace {
/// The pose of arm `arm` (0: needle, 1: probe) in a pair.
KDL::Frame& tool(planning::DualPose& pair, std::size_t arm) { return arm == 0 ? pair.first : pair.second; }
const KDL::Frame& tool(const planning::DualPose& pair, std::size_t arm) { return arm == 0 ? pair.first : pair.second; }
}  // namespace

bool PuncturingMotionPlanner::reusePath(const planning::JointState& start, const planning::DualPose& start_poses,
                                        const planning::DualPose& goal, planning::PlanResult& result) {
  if (paths_.empty()) return false;
  // The moving robot's joints decide (the other holds its tool where it is, e.g. the UR5 its
  // probe where the skin pushed it, a few mm from where the walk put it): the verified path is
  // taken with the other robot where it really is.
  planning::StateValidator& scene = *validator();
  const char* moving = arm_index_ == 0 ? "isur" : "ur5";  // the robots of puncturing.scene
  std::size_t robot = scene.scene().robots.size();
  for (std::size_t r = 0; r < scene.scene().robots.size(); ++r)
    if (scene.scene().robots[r].name == moving) robot = r;
  const task::CheckedPath& next = paths_.front();
  if (robot == scene.scene().robots.size() || next.start.size() != start.size()) return false;
  const std::size_t from = scene.jointOffset(robot), to = from + scene.model(robot).jointCount();
  for (std::size_t j = from; j < to; ++j)
    if (std::abs(start[j] - next.start[j]) > kReuseTolerance) return false;  // elsewhere: not the walk's query
  const std::size_t own = arm_index_, other = 1 - arm_index_;
  if (!KDL::Equal(tool(next.goal, own), tool(goal, own), kReuseTolerance)) {
    // Another goal alternative than the walk took from here: the run takes the walk's, whose way
    // was verified (a search may find a way to this one that was not).
    result = planning::PlanResult{};
    result.status = planning::PlanStatus::NoSolution;
    result.message = "not the goal alternative the procedure's verification took from here";
    return true;
  }
  // The verified path of this robot, from where it is to the goal asked, the other held where it
  // is: each waypoint checked again in that state.
  planning::PlanResult reused = next.result;
  reused.waypoints.front() = start_poses;
  tool(reused.waypoints.back(), own) = tool(goal, own);
  for (std::size_t k = 0; k < reused.waypoints.size(); ++k) {
    tool(reused.waypoints[k], other) = tool(start_poses, other);
    planning::JointState& q = reused.joint_waypoints[k];
    for (std::size_t j = 0; j < q.size(); ++j)
      if (j < from || j >= to || k == 0) q[j] = start[j];
    if (!scene.checkJoints(q).valid()) return false;
  }
  // Where the robot is may differ from where the walk put it (a probe pressed on the skin): the
  // straight way from there onto the verified path is checked as a motion primitive is.
  if (reused.waypoints.size() > 1 && !joiner_->checkMotion(start, start_poses, reused.waypoints[1]).solved())
    return false;
  reused.message = "the path verified with the procedure (" + reused.message + ")";
  result = std::move(reused);
  paths_.erase(paths_.begin());
  return true;
}

void PuncturingMotionPlanner::refuseProcedure(const std::string& line) {
  last_refusal_ = line;
  refusal_.write(line);
  last_verification_ = "refused: " + line;
  std::fprintf(stderr, "[cobra] '%s': procedure refused before any motion: %s\n", name().c_str(), line.c_str());
  emitEvent("e_procedure_refused");
}

bool PuncturingMotionPlanner::takeNavigatedPlan() {
  if (plan_) return true;  // taken once: the procedure is verified for it
  // Asked before they came: waits for them (their arrival wakes this component: event ports).
  if (!navigation_.read(plan_in_, abdomen_frame_)) return false;
  puncturing::PuncturingPlan plan;
  const std::string refusal =
      puncturing_navigation::buildPlan(navigation_.points, navigation_.registration, *preoperative_, plan);
  if (!refusal.empty()) {
    verify_pending_ = false;  // answered: refused
    refuseProcedure("navigation refused: " + refusal);
    return false;
  }
  plan_ = std::move(plan);
  abdomen_ = plan_->preoperative.abdomen_in_task;
  return true;
}

void PuncturingMotionPlanner::verify() {
  if (preoperative_) {
    if (!takeNavigatedPlan()) return;
  } else {
    KDL::Frame sample;
    if (abdomen_frame_.read(sample) != core::FlowStatus::NoData) abdomen_ = sample;
  }
  planning::JointState joints;
  std::string why;
  // Asked before the robots' first joints arrived (the probe's chart asks at its start): the
  // walk waits for them (a new measured pose triggers this component).
  if (!latestJoints(joints, why)) return;
  verify_pending_ = false;
  planning::StateValidator& scene = *validator();
  planning::DualPose tools;
  if (!scene.toolPoses(joints, tools)) return refuseProcedure("the measured joints have no tool poses");
  // This arm's chart plans with this planner, the other's with one of the same options at the
  // other robot's speeds; each from the seed its first query will use.
  planning::PlannerOptions other_options = planner()->options();
  other_options.max_linear_velocity = other_max_vel_();
  other_options.max_angular_velocity = other_max_ang_vel_();
  planning::MotionPlanner own(scene, planner()->options()), other(scene, other_options);
  joiner_ = std::make_unique<planning::MotionPlanner>(scene, planner()->options());
  task::PlannerStepVerifier verifier(arm_index_ == 0 ? std::array{&own, &other} : std::array{&other, &own}, scene,
                                     joints);
  puncturing::PlanDatums datums(*plan_, abdomen_);
  const std::vector<task::ProcedureStep> steps = puncturing::procedureSteps(plan_->needles.size());
  const task::ProcedureVerdict verdict =
      task::walkProcedure(*table_, table_file_(), puncturing::puncturingVocabulary().arms, steps,
                          {tools.first, tools.second}, datums, verifier);
  if (!verdict.ok) return refuseProcedure(verdict.refusal.text(table_file_()));
  last_refusal_.clear();
  paths_.clear();
  for (const task::CheckedPath& path : verifier.paths())
    if (path.step.arm == arm_index_) paths_.push_back(path);  // this planner's; the other's are its own
  last_verification_ = "verified: " + std::to_string(steps.size()) + " motions of " +
                       std::to_string(plan_->needles.size()) + " needles, " +
                       std::to_string(verifier.validityChecks()) + " validity checks";
  emitEvent("e_procedure_verified");
}

}  // namespace cobra::components
