#include "cobra/components/puncturing/navigation_plan.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "cobra/puncturing/probe_plan.hpp"

namespace cobra::components::puncturing_navigation {

namespace {

std::string millimetres(const KDL::Vector& v) {
  char text[96];
  std::snprintf(text, sizeof text, "%.1f, %.1f, %.1f mm", 1000.0 * v.x(), 1000.0 * v.y(), 1000.0 * v.z());
  return text;
}

}  // namespace

std::string buildPlan(const types::PointList& points, const KDL::Frame& registration,
                      const puncturing::PreoperativeInfo& preoperative, puncturing::PuncturingPlan& plan) {
  const std::string source = kPlanSource;
  // Each needle's two points, in the order its first point comes.
  struct Ends {
    std::string name;
    const types::NamedPoint* entry = nullptr;
    const types::NamedPoint* target = nullptr;
    int first = 0;  // 1-based index of its first point
  };
  std::vector<Ends> needles;
  for (std::size_t k = 0; k < points.count; ++k) {
    const types::NamedPoint& p = points.points[k];
    const std::string_view name = p.name.view();
    const std::size_t dot = name.rfind('.');
    const std::string_view needle = dot == std::string_view::npos ? std::string_view{} : name.substr(0, dot);
    const std::string_view end = dot == std::string_view::npos ? std::string_view{} : name.substr(dot + 1);
    if (needle.empty() || (end != "entry" && end != "target"))
      return source + ":" + std::to_string(k + 1) + ": point '" + std::string(name) +
             "': expected a name NEEDLE.entry or NEEDLE.target";
    Ends* ends = nullptr;
    for (Ends& e : needles)
      if (e.name == needle) ends = &e;
    if (ends == nullptr) {
      needles.push_back({std::string(needle), nullptr, nullptr, static_cast<int>(k + 1)});
      ends = &needles.back();
    }
    const types::NamedPoint*& slot = end == "entry" ? ends->entry : ends->target;
    if (slot != nullptr)
      return source + ":" + std::to_string(k + 1) + ": point '" + std::string(name) + "' comes twice";
    slot = &p;
  }
  if (needles.empty()) return source + ": no points; expected NEEDLE.entry and NEEDLE.target of each needle";
  plan = puncturing::PuncturingPlan{};
  plan.preoperative = preoperative;
  for (const Ends& e : needles) {
    if (e.entry == nullptr || e.target == nullptr)
      return source + ":" + std::to_string(e.first) + ": needle '" + e.name + "': no " +
             (e.entry == nullptr ? "entry" : "target") + " point (" + e.name + (e.entry == nullptr ? ".entry" : ".target") +
             ")";
    plan.needles.push_back({e.name, e.entry->position, e.target->position, 0.0, e.first});
  }
  try {
    plan.probes = puncturing::probePlan(plan.needles, preoperative, source);  // validate()s the whole plan
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  // The registration the rest of the deployment was set up with (the planner's phantom, the
  // monitors' regions): the navigation's may differ from it only within the tolerance.
  const KDL::Frame& set_up = preoperative.abdomen_in_task;
  const double offset = (registration.p - set_up.p).Norm();
  KDL::Vector axis;
  const double angle = (set_up.M.Inverse() * registration.M).GetRotAngle(axis);
  if (offset > kRegistrationTolerance || angle > kRegistrationAngleTolerance) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "registration: frame A lies %.1f mm and %.2f deg from the preoperative abdomen the planning scene, "
                  "the monitors and the patient were set up with; at most %.1f mm and %.2f deg can be taken",
                  1000.0 * offset, angle * 180.0 / M_PI, 1000.0 * kRegistrationTolerance,
                  kRegistrationAngleTolerance * 180.0 / M_PI);
    return text;
  }
  plan.preoperative.abdomen_in_task = registration;
  return {};
}

std::string describe(const puncturing::PuncturingPlan& plan) {
  double roll = 0, pitch = 0, yaw = 0;
  const KDL::Frame& a = plan.preoperative.abdomen_in_task;
  a.M.GetRPY(roll, pitch, yaw);
  char rotation[96];
  std::snprintf(rotation, sizeof rotation, "%.2f, %.2f, %.2f deg", roll * 180.0 / M_PI, pitch * 180.0 / M_PI,
                yaw * 180.0 / M_PI);
  std::string text = "registration (" + millimetres(a.p) + "; " + rotation + "), plan of " +
                     std::to_string(plan.needles.size()) + " needle" + (plan.needles.size() == 1 ? "" : "s") + ":";
  for (const puncturing::PlannedNeedle& n : plan.needles)
    text += " " + n.name + " entry (" + millimetres(n.entry) + ") target (" + millimetres(n.target) + ")";
  return text;
}

}  // namespace cobra::components::puncturing_navigation
