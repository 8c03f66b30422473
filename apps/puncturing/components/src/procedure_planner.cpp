#include "cobra/components/puncturing/procedure_planner.hpp"

#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>

#include "cobra/puncturing/procedure.hpp"
#include "cobra/task/planned_walk.hpp"

namespace cobra::components {

PuncturingMotionPlanner::PuncturingMotionPlanner(std::string name) : MotionPlannerComponent(std::move(name)) {
  for (core::Property<std::string>* file : {&preoperative_file_, &cryo_plan_file_, &probe_plan_file_, &table_file_})
    addProperty(*file);
  addProperty(probe_max_vel_.range(1e-6, 10.0));
  addProperty(probe_max_ang_vel_.range(1e-6, 100.0));
  addPort(abdomen_frame_);
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
  const std::pair<const core::Property<std::string>*, const char*> files[] = {
      {&preoperative_file_, "preoperative_info_file"}, {&cryo_plan_file_, "cryo_plan_file"},
      {&probe_plan_file_, "US_pose_plan_file"}, {&table_file_, "state_table_file"}};
  for (const auto& [file, name] : files) {
    if ((*file)().empty()) return refuse(std::string("property ") + name + " is empty; give the path of its file");
  }
  try {
    plan_ = puncturing::loadPlan(preoperative_file_(), cryo_plan_file_(), probe_plan_file_());
    table_ = puncturing::parseStateTable(puncturing::readText(table_file_()), table_file_());
  } catch (const std::invalid_argument& e) {
    plan_.reset();
    table_.reset();
    return refuse(e.what());
  }
  abdomen_ = plan_->preoperative.abdomen_in_task;
  last_refusal_.clear();
  last_verification_.clear();
  return true;
}

void PuncturingMotionPlanner::updateHook() {
  MotionPlannerComponent::updateHook();
  if (verify_request_.take()) verify();
}

bool PuncturingMotionPlanner::reusePath(const planning::JointState& start, const planning::DualPose& start_poses,
                                        const planning::DualPose& goal, planning::PlanResult& result) {
  if (paths_.empty()) return false;
  // The needle robot's joints decide (the UR5 holds its probe where the skin pushed it, a few mm
  // from where the walk put it): the verified path is taken with the UR5 where it really is.
  planning::StateValidator& scene = *validator();
  std::size_t isur = scene.scene().robots.size();
  for (std::size_t r = 0; r < scene.scene().robots.size(); ++r)
    if (scene.scene().robots[r].name == "isur") isur = r;
  const task::CheckedPath& next = paths_.front();
  if (isur == scene.scene().robots.size() || next.start.size() != start.size()) return false;
  const std::size_t from = scene.jointOffset(isur), to = from + scene.model(isur).jointCount();
  for (std::size_t j = from; j < to; ++j)
    if (std::abs(start[j] - next.start[j]) > kReuseTolerance) return false;  // elsewhere: not the walk's query
  if (!KDL::Equal(next.goal.first, goal.first, kReuseTolerance)) {
    // Another goal alternative than the walk took from here: the run takes the walk's, whose way
    // was verified (a search may find a way to this one that was not).
    result = planning::PlanResult{};
    result.status = planning::PlanStatus::NoSolution;
    result.message = "not the goal alternative the procedure's verification took from here";
    return true;
  }
  // The verified path of the needle, from where it is, the UR5 held where it is: each waypoint
  // checked again in that state.
  planning::PlanResult reused = next.result;
  reused.waypoints.front() = start_poses;
  reused.waypoints.back().first = goal.first;
  for (std::size_t k = 0; k < reused.waypoints.size(); ++k) {
    reused.waypoints[k].second = start_poses.second;
    planning::JointState& q = reused.joint_waypoints[k];
    for (std::size_t j = 0; j < q.size(); ++j)
      if (j < from || j >= to || k == 0) q[j] = start[j];
    if (!scene.checkJoints(q).valid()) return false;
  }
  reused.message = "the path verified with the procedure (" + reused.message + ")";
  result = std::move(reused);
  paths_.erase(paths_.begin());
  return true;
}

void PuncturingMotionPlanner::refuseProcedure(const std::string& line) {
  last_refusal_ = line;
  last_verification_ = "refused: " + line;
  std::fprintf(stderr, "[cobra] '%s': procedure refused before any motion: %s\n", name().c_str(), line.c_str());
  emitEvent("e_procedure_refused");
}

void PuncturingMotionPlanner::verify() {
  KDL::Frame sample;
  if (abdomen_frame_.read(sample) != core::FlowStatus::NoData) abdomen_ = sample;
  planning::JointState joints;
  std::string why;
  if (!latestJoints(joints, why)) return refuseProcedure("the robots' start is unknown: " + why);
  planning::StateValidator& scene = *validator();
  planning::DualPose tools;
  if (!scene.toolPoses(joints, tools)) return refuseProcedure("the measured joints have no tool poses");
  // The needle's chart plans with this planner, the probe's with one of the same options at the
  // probe's speeds; each from the seed its first query will use.
  planning::PlannerOptions probe_options = planner()->options();
  probe_options.max_linear_velocity = probe_max_vel_();
  probe_options.max_angular_velocity = probe_max_ang_vel_();
  planning::MotionPlanner needle(scene, planner()->options()), probe(scene, probe_options);
  task::PlannerStepVerifier verifier({&needle, &probe}, scene, joints);
  puncturing::PlanDatums datums(*plan_, abdomen_);
  const std::vector<task::ProcedureStep> steps = puncturing::procedureSteps(plan_->needles.size());
  const task::ProcedureVerdict verdict =
      task::walkProcedure(*table_, table_file_(), puncturing::puncturingVocabulary().arms, steps,
                          {tools.first, tools.second}, datums, verifier);
  if (!verdict.ok) return refuseProcedure(verdict.refusal.line_text(table_file_()));
  last_refusal_.clear();
  paths_.clear();
  for (const task::CheckedPath& path : verifier.paths())
    if (path.step.arm == 0) paths_.push_back(path);  // this planner's (the probe's plans are its own)
  last_verification_ = "verified: " + std::to_string(steps.size()) + " motions of " +
                       std::to_string(plan_->needles.size()) + " needles, " +
                       std::to_string(verifier.validityChecks()) + " validity checks";
  emitEvent("e_procedure_verified");
}

}  // namespace cobra::components
