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
constexpr const char* kMotionSteps[] = {"Switching", "AskingGoal", "Planning", "Generating", "Moving", "Arrived",
                                        "Paused"};

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
  plot::Series tracking{"|commanded - measured|", {}, {}};
  plot::Series needle_tank{"needle robot tank", {}, {}};
  plot::Series probe_tank{"probe robot tank", {}, {}};
  plot::Series min_distance{"minimum collision distance", {}, {}};
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
  out.push_back({"Commanded and measured needle pose",
                 {panel("needle tip height", "t [s]", "z [m]", {s.commanded_z, s.measured_z}),
                  panel("tracking error", "t [s]", "error [m]", {s.tracking})}});
  out.push_back({"Energy tanks of the variable admittances", {panel("tank energy", "t [s]", "T [J]",
                                                                    {s.needle_tank, s.probe_tank})}});
  out.push_back({"Minimum collision distance (motion planner)", {panel("distance of the measured state", "t [s]",
                                                                       "distance [m]", {s.min_distance})}});
  for (plot::Figure& f : out)
    std::erase_if(f.panels, [](const plot::Panel& p) { return p.series.empty(); });
  std::erase_if(out, [](const plot::Figure& f) { return f.panels.empty(); });
  return out;
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

  ProcedureResult result;
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
      "axial force [N],depth [m],needle tank [J],probe tank [J],min collision distance [m]\n";
  while (clock.now() < limit) {
    clock.advance(kStep);
    ++step;
    const double t = std::chrono::duration<double>(clock.now()).count();
    const std::string needle_state(needle_task.activeState()), us_state(us_task.activeState());

    for (auto& [source, reader] : event_taps) {
      std::string name;
      while (reader->readText(name) == core::FlowStatus::NewData) {
        result.events.push_back({t, source, name, onUsSide(source) ? us_state : needle_state});
        result.log.push_back(source + ": " + name.substr(0, name.find(' ')));
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
    if (step % kSamplesEvery == 0) {
      double f = NAN, d = NAN, needle_energy = NAN, probe_energy = NAN, distance = NAN;
      KDL::Frame tip;
      const bool have_tip = measured.read(tip);
      if (axial.read(f)) addPoint(signals.force, t, f);
      if (depth.read(d)) addPoint(signals.depth, t, d);
      if (d > 0.0) addPoint(signals.force_vs_depth, d, f);
      if (have_tip) {
        addPoint(signals.measured_z, t, tip.p.z());
        if (have_command) {
          addPoint(signals.commanded_z, t, last_command.p.z());
          addPoint(signals.tracking, t, (last_command.p - tip.p).Norm());
        }
      }
      if (needle_tank.read(needle_energy)) addPoint(signals.needle_tank, t, needle_energy);
      if (probe_tank.read(probe_energy)) addPoint(signals.probe_tank, t, probe_energy);
      if (min_distance.read(distance)) addPoint(signals.min_distance, t, distance);
      if (!options.report_folder.empty()) {
        const KDL::Vector m = have_tip ? tip.p : KDL::Vector(NAN, NAN, NAN);
        const KDL::Vector c = have_command ? last_command.p : KDL::Vector(NAN, NAN, NAN);
        char row[320];
        std::snprintf(row, sizeof row, "%.3f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.4f,%.6f,%.4f,%.4f,%.5f\n", t, m.x(), m.y(),
                      m.z(), c.x(), c.y(), c.z(), f, d, needle_energy, probe_energy, distance);
        signals_csv += row;
      }
    }
    if (needle_state == kDoneState && us_state == kDoneState) {
      result.completed = true;
      break;
    }
  }
  result.duration = std::chrono::duration<double>(clock.now()).count();
  result.needle_states = timeline.statesEntered("needle chart");
  result.us_states = timeline.statesEntered("ultrasound chart");
  say(result.duration, result.completed ? "procedure complete" : "procedure NOT complete (time limit)");

  if (!options.report_folder.empty()) {
    report::RunReport run;
    run.title = "Puncturing procedure: " + options.scenario.filename().string();
    int faults = 0, reactions = 0;
    for (const report::EventRecord& e : result.events) {
      if (e.event == "e_forbidden_region" || e.event == "e_force_over_threshold" || e.event == "e_plan_failed" ||
          e.event == "e_needle_trapped" || e.event == "e_needle_lost")
        ++faults;
      if (e.event == "e_recover" || e.event == "e_take_over") ++reactions;
    }
    std::string errors;
    for (const NeedlePlacement& p : result.placements)
      errors += (errors.empty() ? "" : ", ") + std::to_string(p.error_mm).substr(0, 4) + " mm";
    const int planned = frames.call<int>("needleCount");
    run.summary = {{"scenario", options.scenario.string()},
                   {"result", result.completed ? "complete" : "not complete"},
                   {"needles placed", std::to_string(result.placements.size()) + " of " + std::to_string(planned)},
                   {"placement error per needle", errors.empty() ? "-" : errors},
                   {"duration (simulated)", seconds(result.duration)},
                   {"faults detected", std::to_string(faults)},
                   {"surgeon reactions", std::to_string(reactions)},
                   {"deployment/configuration switches", std::to_string(result.switches.size())}};
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
