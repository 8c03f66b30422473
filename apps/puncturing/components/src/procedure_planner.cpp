#include "cobra/components/puncturing/procedure_planner.hpp"

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
  last_verification_ = "verified: " + std::to_string(steps.size()) + " motions of " +
                       std::to_string(plan_->needles.size()) + " needles, " +
                       std::to_string(verifier.validityChecks()) + " validity checks";
  emitEvent("e_procedure_verified");
}

}  // namespace cobra::components
