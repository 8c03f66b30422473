#include "cobra/components/puncturing/procedure_planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>

#include "cobra/components/puncturing/navigation_plan.hpp"
#include "cobra/puncturing/procedure.hpp"
#include "cobra/task/planned_walk.hpp"
#include "cobra/task/verified_paths.hpp"

namespace cobra::components {

PuncturingMotionPlanner::PuncturingMotionPlanner(std::string name) : MotionPlannerComponent(std::move(name)) {
  for (core::Property<std::string>* file : {&preoperative_file_, &cryo_plan_file_, &probe_plan_file_, &table_file_})
    addProperty(*file);
  addProperty(arm_);
  addProperty(plan_source_);
  addProperty(other_max_vel_.range(1e-6, 10.0));
  addProperty(other_max_ang_vel_.range(1e-6, 100.0));
  addProperty(walk_);
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
  forgetPaths();  // whatever was verified was verified with the old properties
  if (!MotionPlannerComponent::configureHook()) return false;
  if (arm_() != "needle" && arm_() != "probe") return refuse("property arm is '" + arm_() + "'; expected needle or probe");
  arm_index_ = arm_() == "needle" ? 0 : 1;
  // The robots the walk moves and the run's paths are followed by, by arm.
  const planning::SceneDescription& scene = validator()->scene();
  for (std::size_t arm = 0; arm < 2; ++arm) {
    std::size_t r = 0;
    while (r < scene.robots.size() && scene.robots[r].name != kRobotNames[arm]) ++r;
    if (r == scene.robots.size())
      return refuse("scene_file '" + getProperty<std::string>("scene_file") + "' has no robot '" + kRobotNames[arm] +
                    "'; the procedure's verification expects the needle robot 'isur' and the probe robot 'ur5'");
    if (arm == arm_index_) robot_index_ = r;
  }
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

void PuncturingMotionPlanner::forgetPaths() { follower_.reset(); }

bool PuncturingMotionPlanner::reusePath(const planning::JointState& start, const planning::DualPose& start_poses,
                                        const planning::DualPose& goal, std::size_t alternative,
                                        planning::PlanResult& result) {
  return follower_ && follower_->follow(start, start_poses, goal, alternative, result);
}

void PuncturingMotionPlanner::refuseProcedure(const std::string& line, double seconds) {
  forgetPaths();
  last_refusal_ = line;
  refusal_.write(line);
  last_verification_ = "refused: " + line;
  std::fprintf(stderr, "[cobra] '%s': procedure refused before any motion: %s (walked in %.3f s of wall time)\n",
               name().c_str(), line.c_str(), seconds);
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
  if (!walk_()) {
    forgetPaths();
    last_refusal_.clear();
    last_verification_ = "not walked (verify_walk is false)";
    std::fprintf(stderr, "[cobra] '%s': procedure NOT verified (verify_walk is false)\n", name().c_str());
    emitEvent("e_procedure_verified");
    return;
  }
  planning::StateValidator& scene = *validator();
  planning::DualPose tools;
  if (!scene.toolPoses(joints, tools)) return refuseProcedure("the measured joints have no tool poses");
  // This arm's chart plans with this planner, the other's with one of the same options at the
  // other robot's speeds; each from the seed its first query will use.
  planning::PlannerOptions other_options = planner()->options();
  other_options.max_linear_velocity = other_max_vel_();
  other_options.max_angular_velocity = other_max_ang_vel_();
  planning::MotionPlanner own(scene, planner()->options()), other(scene, other_options);
  task::PlannerStepVerifier verifier(arm_index_ == 0 ? std::array{&own, &other} : std::array{&other, &own}, scene,
                                     joints);
  puncturing::PlanDatums datums(*plan_, abdomen_);
  const auto started = std::chrono::steady_clock::now();
  const std::vector<task::ProcedureStep> steps = puncturing::procedureSteps(plan_->needles.size());
  const task::ProcedureVerdict verdict =
      task::walkProcedure(*table_, table_file_(), puncturing::puncturingVocabulary().arms, steps,
                          {tools.first, tools.second}, datums, verifier);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (!verdict.ok) return refuseProcedure(verdict.refusal.text(table_file_()), seconds);
  last_refusal_.clear();
  // This planner's paths (the other's are its own), to follow in the run.
  std::vector<task::CheckedPath> paths;
  std::vector<std::string> names;
  for (const task::CheckedPath& path : verifier.paths()) {
    if (path.step.arm != arm_index_) continue;
    paths.push_back(path);
    names.push_back("task state '" + path.step.state + "', " + datums.itemName(path.step.item));
  }
  follower_ = std::make_unique<task::VerifiedPaths>(scene, planner()->options(), robot_index_, arm_index_);
  follower_->assign(std::move(paths), std::move(names));
  last_verification_ = "verified: " + std::to_string(steps.size()) + " motions of " +
                       std::to_string(plan_->needles.size()) + " needles, " +
                       std::to_string(verifier.validityChecks()) + " validity checks, " + std::to_string(seconds) +
                       " s of wall time";
  std::fprintf(stderr, "[cobra] '%s': procedure %s\n", name().c_str(), last_verification_.c_str());
  emitEvent("e_procedure_verified");
}

}  // namespace cobra::components
