#include "cobra/puncturing/procedure.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>

#include <kdl/frames.hpp>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/components/coordination/supervisor.hpp"
#include "cobra/components/planning/planning_scene_component.hpp"
#include "cobra/components/puncturing/package.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"

namespace cobra::puncturing {
namespace {

using namespace std::chrono_literals;

// Instance names given by puncturing.lua.
constexpr const char* kNeedleTask = "NeedleTaskSup";
constexpr const char* kUsTask = "ProbeTaskSup";
constexpr const char* kDoneState = "root.Done";
constexpr auto kStep = 1ms;                 // the control and coordination period
constexpr int kSamplesEvery = 10;           // steps between two plotted samples
constexpr int kClearanceEvery = 2;         // steps between two clearance samples (IK + FCL of both robots)
constexpr const char* kSafeStopState = "root.SafeStop";
constexpr double kSafeStopLinger = 2.0;    // s the run goes on after a chart's safe stop (the other one stops too)
constexpr const char* kMotionSteps[] = {"Switching", "AskingGoal", "Planning", "Generating", "Moving", "Arrived",
                                        "Paused"};
// The events a chart reacts to as a failure (charts/*.lua: faults, goal missed): the last one a
// chart saw is the reason of its safe stop.
constexpr const char* kFailures[] = {"e_forbidden_region", "e_force_over_threshold", "e_plan_failed", "e_traj_failed",
                                     "e_no_data", "e_comm_timeout", "e_ik_discontinuity", "e_probe_contact_lost",
                                     "e_needle_goal_missed", "e_us_goal_missed", "e_us_needle_not_found"};

/// A reader of one output port, typed.
template <class T>
class Tap {
 public:
  Tap(core::ComponentRegistry& refs, const std::string& component, const std::string& port) {
    auto& out = dynamic_cast<core::OutputPortBase&>(refs.get(component).port(port));
    reader_ = out.makeReader(component + "_" + port, "puncturing run probe");
    out.connectTo(*reader_, core::ConnPolicy::data());
    typed_ = dynamic_cast<core::InputPort<T>*>(reader_.get());
    if (typed_ == nullptr) throw std::runtime_error("puncturing run: " + component + "." + port + " has another type");
  }
  bool read(T& value) { return typed_->read(value) != core::FlowStatus::NoData; }

 private:
  std::unique_ptr<core::InputPortBase> reader_;
  core::InputPort<T>* typed_ = nullptr;
};

/// The task state a person cares about: a motion's internal steps are folded into the motion.
std::string taskState(std::string_view active) {
  std::string state(active);
  const auto dot = state.rfind('.');
  if (dot == std::string::npos) return state;
  const std::string leaf = state.substr(dot + 1);
  for (const char* step : kMotionSteps)
    if (leaf == step) return state.substr(0, dot);
  return state;
}

/// Which chart an event source belongs to (for the log's "state after").
bool onUsSide(const std::string& source) {
  return source.rfind("Probe", 0) == 0 || source == "UR5" || source == "USMonitor";
}

std::string seconds(double t) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%8.3f s", t);
  return buffer;
}

struct Signals {
  plot::Series force{"axial force on the needle", {}, {}};
  plot::Series depth{"needle depth", {}, {}};
  plot::Series force_vs_depth{"force vs depth", {}, {}};
  plot::Series commanded_z{"commanded tip z", {}, {}};
  plot::Series measured_z{"measured tip z", {}, {}, true};
  plot::Series needle_tank{"needle robot tank", {}, {}};
  plot::Series probe_tank{"probe robot tank", {}, {}};
  // Tracking error per robot (the largest over each 10 ms), with issue 15's acceptance figures.
  plot::Series needle_mm{"I-SUR needle", {}, {}}, needle_deg{"I-SUR needle", {}, {}};
  plot::Series probe_mm{"UR5 probe", {}, {}}, probe_deg{"UR5 probe", {}, {}};
  plot::Series limit_mm{"acceptance (2 mm)", {}, {}, true}, limit_deg{"acceptance (1 deg)", {}, {}, true};
  plot::Series clearance{"clearance (allowed contacts left out)", {}, {}};
  plot::Series threshold{"planner threshold", {}, {}, true};
  std::vector<plot::Series> contacts;  // one per allowed contact
};

void addPoint(plot::Series& series, double x, double y) {
  if (!std::isfinite(x) || !std::isfinite(y)) return;
  series.x.push_back(x);
  series.y.push_back(y);
}

std::vector<plot::Figure> figures(const Signals& s) {
  auto panel = [](std::string title, std::string x, std::string y, std::vector<plot::Series> series) {
    std::erase_if(series, [](const plot::Series& one) { return one.x.empty(); });
    return plot::Panel{std::move(title), std::move(x), std::move(y), std::move(series)};
  };
  std::vector<plot::Figure> out;
  out.push_back({"Needle-tip force against depth", {panel("tissue force along the needle", "depth [m]", "force [N]",
                                                          {s.force_vs_depth})}});
  out.push_back({"Commanded and measured needle pose", {panel("needle tip height", "t [s]", "z [m]",
                                                              {s.commanded_z, s.measured_z})}});
  for (const auto* robot : {&s.needle_mm, &s.probe_mm}) {
    const plot::Series& mm = *robot;
    const plot::Series& deg = robot == &s.needle_mm ? s.needle_deg : s.probe_deg;
    out.push_back({"Tool tracking error, " + mm.label + " (commanded = admittance output, measured)",
                   {panel("position error (largest per 10 ms)", "t [s]", "error [mm]", {mm, s.limit_mm}),
                    panel("orientation error (largest per 10 ms)", "t [s]", "error [deg]", {deg, s.limit_deg})}});
  }
  out.push_back({"Energy tanks of the variable admittances", {panel("tank energy", "t [s]", "T [J]",
                                                                    {s.needle_tank, s.probe_tank})}});
  out.push_back({"Minimum collision distance of the measured state",
                 {panel("clearance against the motion planner's threshold", "t [s]", "distance [m]",
                        {s.clearance, s.threshold}),
                  panel("allowed contacts (0: touching or inside)", "t [s]", "distance [m]", s.contacts)}});
  for (plot::Figure& f : out)
    std::erase_if(f.panels, [](const plot::Panel& p) { return p.series.empty(); });
  std::erase_if(out, [](const plot::Figure& f) { return f.panels.empty(); });
  return out;
}

/// The scene the NeedlePlanner builds from its properties (its validator is its own): what the
/// measured clearance is checked against, with the same threshold, phantom pose and tool frames.
planning::SceneDescription plannerScene(const core::Component& planner) {
  components::PlanningSceneSettings s;
  s.models_folder = planner.getProperty<std::string>("models_folder");
  s.scene_file = planner.getProperty<std::string>("scene_file");
  s.isur_mesh_names = planner.getProperty<std::string>("isur_mesh_names");
  s.ur5_mesh_names = planner.getProperty<std::string>("UR5_mesh_names");
  s.env_mesh_names = planner.getProperty<std::string>("env_mesh_names");
  s.macro_link_list = planner.getProperty<std::vector<double>>("macro_link_list");
  s.micro_link_list = planner.getProperty<std::vector<double>>("micro_link_list");
  s.ur5_link_list = planner.getProperty<std::vector<double>>("UR5_link_list");
  s.mesh_scale = planner.getProperty<double>("mesh_scale");
  s.min_collision_distance = planner.getProperty<double>("min_collision_distance");
  s.phantom_pose = planner.getProperty<KDL::Frame>("phantom_pose");
  s.first_tool_frame = planner.getProperty<KDL::Frame>("first_tool_frame");
  s.second_tool_frame = planner.getProperty<KDL::Frame>("second_tool_frame");
  return components::buildPlanningScene(s);
}

/// The allowed contacts (README.md): the probe pressed on the skin (the planning scene's `allow`)
/// and the needle on and in the tissue.
const std::vector<AllowedContact> kContacts = {{"probe on skin", "us_probe", "phantom"},
                                               {"needle in tissue", "needle", "phantom"}};
constexpr std::size_t kNeedleContact = 1;

/// Follows whether the needle may touch the phantom: from the descent to the skin until the
/// extraction has ended; unchanged in the states between (a reaction, teleoperation, safe stop).
void followNeedleContact(const std::string& state, bool& allowed) {
  for (const char* in : {"MoveToSkin.Descend", "PenetratingSkin", "MoveToTumor", "WaitCryoCycle", "ExtractingNeedle"})
    if (state.find(in) != std::string::npos) {
      allowed = true;
      return;
    }
  for (const char* out : {"MoveToNeedleChange", "WaitNeedleRemoved", "WaitNeedleMounted", "MoveToSkin.Approach",
                          "WaitUSPositioning", "WaitIceballConfig", "Done"})
    if (state.find(out) != std::string::npos) allowed = false;
}

std::string millimetres(double metres) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f mm", 1000.0 * metres);
  return text;
}

/// The robot's deployment is one of its autonomous ones (needle_autonomous_planning, ...).
bool isAutonomous(const std::string& deployment) {
  return deployment.ends_with("_autonomous_planning") || deployment.ends_with("_autonomous_primitives");
}

/// "0.84 mm at 12.345 s (root.InsertingNeedles.MoveToSkin.Approach.Moving)".
std::string worstText(const Worst& worst, const char* unit) {
  char text[96];
  std::snprintf(text, sizeof text, "%.2f %s at %.3f s", worst.value, unit, worst.at);
  return text + (worst.state.empty() ? std::string() : " (" + worst.state + ")");
}

std::vector<std::pair<std::string, std::string>> fidelitySummary(const Fidelity& f) {
  std::vector<std::pair<std::string, std::string>> rows;
  for (const TrackingFigures* robot : {&f.needle, &f.probe}) {
    char above[64];
    std::snprintf(above, sizeof above, "%.3f s above 5 mm of %.1f s sampled", robot->seconds_above_5mm,
                  robot->seconds_sampled);
    rows.push_back({"worst tracking, " + robot->robot + " (autonomous)",
                    worstText(robot->position_mm, "mm") + "; " + worstText(robot->orientation_deg, "deg") + "; " + above});
    rows.push_back({"joints at their velocity limit, " + robot->robot,
                    std::to_string(robot->joint_jumps) + " episodes; fastest " +
                        worstText({100.0 * robot->joint_speed.value, robot->joint_speed.at, robot->joint_speed.state},
                                  "% of the limit")});
  }
  rows.push_back({"IK discontinuity events (e_ik_discontinuity)", std::to_string(f.ik_discontinuities.size())});
  const ClearanceFigures& c = f.clearance;
  char below[96];
  std::snprintf(below, sizeof below, "; %.3f s at or under the threshold; %d unreachable samples", c.seconds_below,
                c.unreachable);
  rows.push_back({"worst clearance (threshold " + millimetres(c.threshold) + ", allowed contacts apart)",
                  std::isinf(c.worst) ? std::string("-")
                                      : millimetres(c.worst) + " at" + seconds(c.worst_at) + " (" + c.worst_pair + "; " +
                                            c.worst_state + ")" + below});
  std::string breaches;
  for (const ClearanceFigures::Breach& b : c.breaches) {
    char text[96];
    std::snprintf(text, sizeof text, " %.3f s, closest %.2f mm at %.3f s", b.seconds, 1000.0 * b.worst, b.at);
    breaches += (breaches.empty() ? "" : "; ") + b.pair + text + " (" + b.state + ")";
  }
  rows.push_back({"pairs at or under the threshold", breaches.empty() ? "none" : breaches});
  std::string contacts;
  for (const auto& [name, distance] : c.contacts)
    contacts += (contacts.empty() ? "" : ", ") + name + " " + (std::isinf(distance) ? "-" : millimetres(distance));
  rows.push_back({"allowed contacts, smallest distance (0: touching)", contacts});
  return rows;
}

bool isFailure(std::string_view event) {
  return std::any_of(std::begin(kFailures), std::end(kFailures), [&](const char* f) { return event == f; }) ||
         event.starts_with("e_deploy_failed_") || event.starts_with("e_configure_failed_");
}


}  // namespace

void addPuncturingPackages(deploy::Configurator& configurator) {
  auto& packages = configurator.packages();
  components::addBuiltinPackages(packages);
  packages.addBuiltin("cobra_puncturing", components::registerPuncturingPackage);
}

ProcedureResult runProcedure(const ProcedureOptions& options) {
  deploy::Configurator configurator;  // lockstep simulation clock
  addPuncturingPackages(configurator);
  script::LuaState lua;
  deploy::LuaDeployer deployer(configurator, lua);
  deployer.run("scenario = [[" + options.scenario.string() + "]]", "=scenario");
  if (!options.surgeon_file.empty()) deployer.run("surgeon_file = [[" + options.surgeon_file.string() + "]]", "=surgeon");
  deployer.runFile(options.deployment_file.string());
  if (!options.extra_lua.empty()) deployer.run(options.extra_lua, "=extra_lua");

  core::ComponentRegistry& refs = configurator.getReferences();
  const auto& needle_task = dynamic_cast<const components::Supervisor&>(refs.get(kNeedleTask));
  const auto& us_task = dynamic_cast<const components::Supervisor&>(refs.get(kUsTask));
  core::Component& frames = refs.get("NeedleFrames");
  ProcedureResult result;

  // Every component's events, as the log sees them.
  std::vector<std::pair<std::string, std::unique_ptr<core::InputPortBase>>> event_taps;
  for (const core::ComponentInfo& info : refs.describeAll()) {
    // The components' events, and what the supervisors' charts emit.
    for (const char* port : {"events", "outputEvents"}) {
      auto* out = dynamic_cast<core::OutputPortBase*>(refs.get(info.name).findPort(port));
      if (out == nullptr) continue;
      auto reader = out->makeReader(info.name + "_" + port, "puncturing event log");
      out->connectTo(*reader, core::ConnPolicy::buffer(256));
      event_taps.emplace_back(info.name, std::move(reader));
    }
  }
  Tap<double> axial(refs, "Patient", "needleAxialForce"), depth(refs, "Patient", "needleDepth");
  Tap<double> needle_tank(refs, "NeedleAdmittance", "tankEnergy"), probe_tank(refs, "ProbeAdmittance", "tankEnergy");
  Tap<double> min_distance(refs, "NeedlePlanner", "minDistance");
  Tap<KDL::Frame> commanded(refs, "NeedleAdmittance", "admPose"), measured(refs, "ISUR", "measCartPose");
  // Fidelity (fidelity.hpp): both robots' commanded and measured poses and measured joints, and
  // the clearance of the measured state in the needle planner's scene.
  Tap<KDL::Frame> probe_commanded(refs, "ProbeAdmittance", "admPose"), probe_measured(refs, "UR5", "measCartPose");
  Tap<KDL::JntArray> needle_joints(refs, "ISUR", "measJointPosition"), probe_joints(refs, "UR5", "measJointPosition");
  const double period = std::chrono::duration<double>(kStep).count();
  auto limits = [&](const char* robot) {
    auto v = refs.get(robot).getProperty<std::vector<double>>("max_velocity");
    if (v.empty())
      throw std::runtime_error(std::string("puncturing run: ") + robot +
                               ".max_velocity is empty: the joint-jump check needs the robot's joint velocity limits "
                               "(rad/s, m/s), set them in the deployment (deployment/world.lua)");
    return v;
  };
  TrackingMonitor needle_tracking("I-SUR needle", limits("ISUR"), period);
  TrackingMonitor probe_tracking("UR5 probe", limits("UR5"), period);
  ClearanceMonitor clearance(plannerScene(refs.get("NeedlePlanner")), kContacts);
  const std::size_t isur_index = clearance.robotIndex("isur"), ur5_index = clearance.robotIndex("ur5");
  std::vector<KDL::JntArray> robot_joints(std::max(isur_index, ur5_index) + 1);
  bool needle_contact_allowed = false;
  ClearanceSample last_clearance;
  ClearanceFigures& clear = result.fidelity.clearance;
  clear.threshold = clearance.threshold();
  for (const AllowedContact& c : clearance.contacts())
    clear.contacts.emplace_back(c.name, std::numeric_limits<double>::infinity());
  std::string last_failure[2];  // the last failure event each chart saw (needle, us): a safe stop's reason
  double safe_stop_at = -1.0;

  report::TimelineRecorder timeline;
  Signals signals;
  auto say = [&](double t, const std::string& what) {
    if (options.progress) options.progress(seconds(t) + "  " + what);
  };
  std::string needle_shown, us_shown, needle_dep, probe_dep, configuration;
  KDL::Frame last_command;
  bool have_command = false;
  std::string previous_needle_state;
  long step = 0;
  const auto limit = std::chrono::duration<double>(options.time_limit);
  auto& clock = configurator.clock();
  clock.setStepObserver(options.step_observer);
  core::Component& patient = refs.get("Patient");
  struct Armed {
    const Injection* injection;
    double due = -1.0;  // s; < 0: its state not entered yet
    bool done = false;
  };
  std::vector<Armed> injections;
  for (const Injection& injection : options.injections) injections.push_back({&injection});
  std::string previous_us_state;
  // The recorded ports, every kSamplesEvery steps (s, m, N, J).
  std::string signals_csv =
      "time [s],tip x [m],tip y [m],tip z [m],commanded x [m],commanded y [m],commanded z [m],"
      "axial force [N],depth [m],needle tank [J],probe tank [J],min collision distance [m],"
      "needle tracking [mm],needle tracking [deg],probe tracking [mm],probe tracking [deg],clearance [m],"
      "clearance threshold [m],needle contact distance [m],probe contact distance [m]\n";
  while (clock.now() < limit) {
    clock.advance(kStep);
    ++step;
    const double t = std::chrono::duration<double>(clock.now()).count();
    const std::string needle_state(needle_task.activeState()), us_state(us_task.activeState());

    for (auto& [source, reader] : event_taps) {
      std::string name;
      while (reader->readText(name) == core::FlowStatus::NewData) {
        const std::string& state = onUsSide(source) ? us_state : needle_state;
        result.events.push_back({t, source, name, state});
        const std::string event = name.substr(0, name.find(' '));
        result.log.push_back(source + ": " + event);
        if (event == "e_ik_discontinuity")
          result.fidelity.ik_discontinuities.push_back(seconds(t) + " " + source + " (" + state + ")");
        if (isFailure(event)) last_failure[onUsSide(source) ? 1 : 0] = source + ": " + event + " at" + seconds(t);
      }
    }
    timeline.observe(t, "needle chart", taskState(needle_state));
    timeline.observe(t, "ultrasound chart", taskState(us_state));
    if (taskState(needle_state) != needle_shown) {
      say(t, "needle      " + (needle_shown = taskState(needle_state)));
      result.log.push_back("needle > " + needle_shown);
    }
    if (taskState(us_state) != us_shown) {
      say(t, "ultrasound  " + (us_shown = taskState(us_state)));
      result.log.push_back("us > " + us_shown);
    }
    auto watch = [&](const std::string& now, std::string& shown, const char* lane, const char* label) {
      if (now == shown) return;
      shown = now;
      timeline.observe(t, lane, now.empty() ? "(none)" : now);
      result.switches.push_back(seconds(t) + " " + label + " " + now);
      result.log.push_back(std::string(label) + " > " + now);
      say(t, std::string("  ") + label + " -> " + now);
    };
    watch(configurator.currentDeployment("needle"), needle_dep, "needle deployment", "needle deployment");
    watch(configurator.currentDeployment("probe"), probe_dep, "probe deployment", "probe deployment");
    watch(configurator.currentConfiguration(), configuration, "configuration", "configuration");

    // The needle placed: where its tip was during the freeze, i.e. when the chart leaves
    // WaitCryoCycle (the insertion motion ends within the monitor's tolerance of the target
    // and settles while the ice forms).
    if (needle_state.find("WaitCryoCycle") == std::string::npos &&
        previous_needle_state.find("WaitCryoCycle") != std::string::npos) {
      KDL::Frame tip;
      const int needle = frames.call<int>("currentNeedle");
      if (measured.read(tip)) {
        const KDL::Frame target = frames.call<KDL::Frame>("plannedTarget", needle);
        result.placements.push_back({needle, t, 1000.0 * (tip.p - target.p).Norm()});
        say(t, "needle " + std::to_string(needle + 1) + " placed, " +
                   std::to_string(result.placements.back().error_mm).substr(0, 4) + " mm from its target");
      }
    }
    // A reaction: say where the needle is (the surgeon's first question).
    if (needle_state == "root.WaitReaction" && previous_needle_state != needle_state) {
      const int current_needle = frames.call<int>("currentNeedle");
      KDL::Frame tip;
      if (current_needle < frames.call<int>("needleCount") && measured.read(tip)) {
        const KDL::Frame target = frames.call<KDL::Frame>("plannedTarget", current_needle);
        char line[160];
        std::snprintf(line, sizeof line, "  needle tip at (%.4f, %.4f, %.4f) m, %.2f mm from its target", tip.p.x(),
                      tip.p.y(), tip.p.z(), 1000.0 * (tip.p - target.p).Norm());
        say(t, line);
      }
    }
    // The cryoablation console: the freeze starts as the needle is placed.
    if (needle_state == "root.WaitCryoCycle" && previous_needle_state != needle_state) patient.call<void>("startFreeze");
    for (Armed& armed : injections) {
      const std::string& now = armed.injection->chart == "us" ? us_state : needle_state;
      const std::string& before = armed.injection->chart == "us" ? previous_us_state : previous_needle_state;
      if (armed.done) continue;
      if (armed.due < 0.0 && now.find(armed.injection->state) != std::string::npos &&
          before.find(armed.injection->state) == std::string::npos)
        armed.due = t + armed.injection->after;
      if (armed.due >= 0.0 && t >= armed.due) {
        armed.done = true;
        say(t, "  injected: " + armed.injection->lua);
        deployer.run(armed.injection->lua, "=injection");
      }
    }
    // A safe stop (charts/task_steps.lua: the same failure again on the retry): say why, once.
    for (const bool us : {false, true}) {
      const std::string& now = us ? us_state : needle_state;
      const std::string& before = us ? previous_us_state : previous_needle_state;
      if (now != kSafeStopState || before == kSafeStopState) continue;
      if (!result.safe_stop) {
        result.safe_stop = true;
        safe_stop_at = t;
        const std::string& failure = last_failure[us ? 1 : 0];
        result.stop_reason = std::string(us ? "ultrasound" : "needle") + " chart stopped safely in " +
                             taskState(before) + ": " + (failure.empty() ? "(no failure event seen)" : failure) +
                             ", the same failure again after the reaction to the first";
        if (failure.find("e_plan_failed") != std::string::npos)
          result.stop_reason +=
              "; planner: " + refs.get(us ? "ProbePlanner" : "NeedlePlanner").call<std::string>("lastPlanResult");
        say(t, "SAFE STOP: " + result.stop_reason);
      }
      result.log.push_back(std::string(us ? "us" : "needle") + " safe stop");
    }
    previous_needle_state = needle_state;
    previous_us_state = us_state;

    KDL::Frame command;
    if (commanded.read(command)) {
      if (have_command && (command.p - last_command.p).Norm() > result.max_command_step) {
        result.max_command_step = (command.p - last_command.p).Norm();
        result.max_command_step_at = t;
      }
      last_command = command;
      have_command = true;
    }
    // Tracking, every step: the samples count while the robot's deployment is autonomous.
    KDL::Frame needle_meas, probe_cmd, probe_meas;
    KDL::JntArray needle_q, probe_q;
    const bool have_needle_q = needle_joints.read(needle_q), have_probe_q = probe_joints.read(probe_q);
    const bool have_needle = measured.read(needle_meas), have_probe = probe_measured.read(probe_meas);
    if (have_command && have_needle)
      needle_tracking.step(t, isAutonomous(configurator.currentDeployment("needle")), needle_state, last_command,
                           needle_meas, have_needle_q ? &needle_q : nullptr);
    if (probe_commanded.read(probe_cmd) && have_probe)
      probe_tracking.step(t, isAutonomous(configurator.currentDeployment("probe")), us_state, probe_cmd, probe_meas,
                          have_probe_q ? &probe_q : nullptr);
    // Clearance of the measured state, every kClearanceEvery steps.
    followNeedleContact(needle_state, needle_contact_allowed);
    if (step % kClearanceEvery == 0 && have_needle && have_probe) {
      const std::vector<bool> allowed{true, needle_contact_allowed};
      if (isur_index < robot_joints.size() && have_needle_q) robot_joints[isur_index] = needle_q;
      if (ur5_index < robot_joints.size() && have_probe_q) robot_joints[ur5_index] = probe_q;
      last_clearance = clearance.measure(needle_meas, probe_meas, allowed, robot_joints, false);
      if (std::isnan(last_clearance.clearance)) {
        ++clear.unreachable;
      } else {
        if (last_clearance.clearance <= clear.threshold) clear.seconds_below += kClearanceEvery * period;
        const bool worse = last_clearance.clearance < clear.worst;
        if (worse || last_clearance.clearance <= clear.threshold) {
          const ClearanceSample named = clearance.measure(needle_meas, probe_meas, allowed, robot_joints, true);
          const std::string states = "needle: " + needle_state + ", us: " + us_state;
          if (worse) clear.worst_pair = named.closest, clear.worst_state = states;
          for (const auto& [pair, distance] : named.under_threshold) {
            auto it = std::find_if(clear.breaches.begin(), clear.breaches.end(),
                                   [&](const ClearanceFigures::Breach& b) { return b.pair == pair; });
            if (it == clear.breaches.end()) it = clear.breaches.insert(it, {pair, distance, t, states, 0.0});
            it->seconds += kClearanceEvery * period;
            if (distance < it->worst) *it = {pair, distance, t, states, it->seconds};
          }
        }
        if (worse) clear.worst = last_clearance.clearance, clear.worst_at = t;
        for (std::size_t i = 0; i < last_clearance.contacts.size() && i < clear.contacts.size(); ++i)
          clear.contacts[i].second = std::min(clear.contacts[i].second, last_clearance.contacts[i]);
      }
    }
    if (step % kSamplesEvery == 0) {
      double f = NAN, d = NAN, needle_energy = NAN, probe_energy = NAN, distance = NAN;
      KDL::Frame tip;
      const bool have_tip = measured.read(tip);
      if (axial.read(f)) addPoint(signals.force, t, f);
      if (depth.read(d)) addPoint(signals.depth, t, d);
      if (d > 0.0) addPoint(signals.force_vs_depth, d, f);
      if (have_tip) {
        addPoint(signals.measured_z, t, tip.p.z());
        if (have_command) addPoint(signals.commanded_z, t, last_command.p.z());
      }
      const auto [needle_mm, needle_deg] = needle_tracking.takeWindowMaximum();
      const auto [probe_mm, probe_deg] = probe_tracking.takeWindowMaximum();
      addPoint(signals.needle_mm, t, needle_mm);
      addPoint(signals.needle_deg, t, needle_deg);
      addPoint(signals.probe_mm, t, probe_mm);
      addPoint(signals.probe_deg, t, probe_deg);
      addPoint(signals.limit_mm, t, kAcceptedTrackingMm);
      addPoint(signals.limit_deg, t, kAcceptedTrackingDeg);
      addPoint(signals.clearance, t, last_clearance.clearance);
      addPoint(signals.threshold, t, clear.threshold);
      signals.contacts.resize(clear.contacts.size());
      for (std::size_t i = 0; i < signals.contacts.size(); ++i) {
        signals.contacts[i].label = clear.contacts[i].first;
        if (i < last_clearance.contacts.size()) addPoint(signals.contacts[i], t, last_clearance.contacts[i]);
      }
      if (needle_tank.read(needle_energy)) addPoint(signals.needle_tank, t, needle_energy);
      if (probe_tank.read(probe_energy)) addPoint(signals.probe_tank, t, probe_energy);
      min_distance.read(distance);  // the planner's own figure (every checked pair, no contact allowed)
      if (!options.report_folder.empty()) {
        const KDL::Vector m = have_tip ? tip.p : KDL::Vector(NAN, NAN, NAN);
        const KDL::Vector c = have_command ? last_command.p : KDL::Vector(NAN, NAN, NAN);
        auto contact = [&](std::size_t i) { return i < last_clearance.contacts.size() ? last_clearance.contacts[i] : NAN; };
        char row[512];
        std::snprintf(row, sizeof row,
                      "%.3f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.4f,%.6f,%.4f,%.4f,%.5f,%.4f,%.4f,%.4f,%.4f,%.5f,%.4f,%.5f,%.5f\n",
                      t, m.x(), m.y(), m.z(), c.x(), c.y(), c.z(), f, d, needle_energy, probe_energy, distance, needle_mm,
                      needle_deg, probe_mm, probe_deg, last_clearance.clearance, clear.threshold, contact(kNeedleContact),
                      contact(0));
        signals_csv += row;
      }
    }
    if (needle_state == kDoneState && us_state == kDoneState) {
      result.completed = true;
      break;
    }
    const auto ended = [](const std::string& state) { return state == kDoneState || state == kSafeStopState; };
    if (result.safe_stop && ((ended(needle_state) && ended(us_state)) || t - safe_stop_at >= kSafeStopLinger)) break;
  }
  result.fidelity.needle = needle_tracking.figures();
  result.fidelity.probe = probe_tracking.figures();
  result.duration = std::chrono::duration<double>(clock.now()).count();
  result.needle_states = timeline.statesEntered("needle chart");
  result.us_states = timeline.statesEntered("ultrasound chart");
  say(result.duration, result.completed   ? "procedure complete"
                       : result.safe_stop ? "procedure NOT complete (safe stop)"
                                          : "procedure NOT complete (time limit)");

  if (!options.report_folder.empty()) {
    report::RunReport run;
    run.title = "Puncturing procedure: " + options.scenario.filename().string();
    int faults = 0, reactions = 0;
    for (const report::EventRecord& e : result.events) {
      if (isFailure(e.event) || e.event == "e_needle_trapped" || e.event == "e_needle_lost") ++faults;
      if (e.event == "e_recover" || e.event == "e_take_over") ++reactions;
    }
    std::string errors;
    for (const NeedlePlacement& p : result.placements)
      errors += (errors.empty() ? "" : ", ") + std::to_string(p.error_mm).substr(0, 4) + " mm";
    const int planned = frames.call<int>("needleCount");
    run.summary = {{"scenario", options.scenario.string()},
                   {"result", result.completed   ? "complete"
                              : result.safe_stop ? "safe stop: " + result.stop_reason
                                                 : "not complete (time limit)"},
                   {"needles placed", std::to_string(result.placements.size()) + " of " + std::to_string(planned)},
                   {"placement error per needle", errors.empty() ? "-" : errors},
                   {"duration (simulated)", seconds(result.duration)},
                   {"faults detected", std::to_string(faults)},
                   {"surgeon reactions", std::to_string(reactions)},
                   {"deployment/configuration switches", std::to_string(result.switches.size())}};
    for (auto& row : fidelitySummary(result.fidelity)) run.summary.push_back(std::move(row));
    run.events = result.events;
    run.timeline = timeline.intervals(result.duration);
    run.figures = figures(signals);
    run.files = {"signals.csv"};
    result.report = report::writeRunFolder(options.report_folder, run);
    std::ofstream csv(options.report_folder / "signals.csv");
    csv << signals_csv;
    if (!csv) throw std::runtime_error("puncturing run: cannot write " + (options.report_folder / "signals.csv").string());
  }
  return result;
}

}  // namespace cobra::puncturing
