#pragma once
/// @file
/// One puncturing procedure in simulation (thesis ch. 4): the deployment file with both robots'
/// controllers, the simulated world and the scripted surgeon, run on the lockstep clock until both
/// task charts are done; then the run folder (event log, recorded signals, HTML report).
/// What `./do demo` runs and what the end-to-end tests drive.

#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "cobra/core/lockstep_clock.hpp"
#include "cobra/puncturing/fidelity.hpp"
#include "cobra/report/run_report.hpp"

namespace cobra::deploy {
class Configurator;
}

namespace cobra::puncturing {

/// A fault injected by a test: Lua run by the deployer (property changes, operation calls,
/// lifecycle of a component) `after` s after chart `chart` ("needle" or "us") entered a task state
/// whose path contains `state`; once.
struct Injection {
  std::string chart;
  std::string state;
  double after = 0.0;  ///< s
  std::string lua;
};

struct ProcedureOptions {
  /// The application's deployment file (apps/puncturing/puncturing.lua).
  std::filesystem::path deployment_file;
  /// Scenario folder (preoperative.txt, cryo_plan.txt, us_plan.txt, surgeon.txt, phantom.txt).
  std::filesystem::path scenario;
  /// Where to write the run folder; empty: no report.
  std::filesystem::path report_folder;
  /// Simulated time after which the run stops unfinished [s].
  double time_limit = 900.0;
  /// Lua run after the deployment file (tests: a fault to inject, a property to change).
  std::string extra_lua;
  /// The surgeon's script (surgeon.txt format); empty: the scenario's.
  std::filesystem::path surgeon_file;
  /// Faults injected during the run, each once.
  std::vector<Injection> injections;
  /// Called after every component step with its wall-clock duration (core::LockstepClock).
  core::LockstepClock::StepObserver step_observer;
  /// Called with one line per task state change and per switch (nullptr: quiet).
  std::function<void(const std::string&)> progress;
};

/// A needle at its target: where the tip ended and how far from the planned target.
struct NeedlePlacement {
  int needle = 0;
  double time = 0.0;      ///< s, when the needle chart left WaitCryoCycle (the tip held during the freeze)
  double error_mm = 0.0;  ///< mm, measured tip to planned target
};

/// Clearance of the measured state over a run (ClearanceMonitor, sampled every 2 ms).
struct ClearanceFigures {
  double threshold = 0.0;  ///< m, the motion planner's min_collision_distance
  /// m: the smallest clearance outside the allowed contacts in force; +inf before any sample.
  double worst = std::numeric_limits<double>::infinity();
  double worst_at = 0.0;      ///< s
  std::string worst_pair;     ///< "object/object", the closest pair then
  std::string worst_state;    ///< "needle: STATE, us: STATE" then
  double seconds_below = 0.0; ///< s of samples at or under the threshold
  int unreachable = 0;        ///< samples whose measured pose the scene's robot models cannot reach
  /// A pair of objects that came at or under the threshold: its smallest distance [m], when [s],
  /// both charts' states then, and for how long in all [s].
  struct Breach {
    std::string pair;
    double worst = 0.0;
    double at = 0.0;
    std::string state;
    double seconds = 0.0;
  };
  std::vector<Breach> breaches;  ///< in order of first breach
  /// Per allowed contact (ClearanceMonitor::contacts order): its name and smallest distance [m].
  std::vector<std::pair<std::string, double>> contacts;
};

/// "The robot did what it was told" (issue 15), measured over the autonomous motions: a robot's
/// samples count while its deployment is one of its two autonomous deployments (the trajectory
/// generator commands it: planned motions, motion primitives, and the holds between them);
/// teleoperation is left out. Commanded = the variable admittance's output (the robot's
/// desCartPose), measured = the robot's measCartPose, every 1 ms step.
struct Fidelity {
  TrackingFigures needle{"I-SUR needle", {}, {}, 0.0, 0.0, 0, {}, {}};
  TrackingFigures probe{"UR5 probe", {}, {}, 0.0, 0.0, 0, {}, {}};
  /// Every e_ik_discontinuity event of the run: "t s SOURCE (chart state)".
  std::vector<std::string> ik_discontinuities;
  ClearanceFigures clearance;
};

struct ProcedureResult {
  bool completed = false;  ///< both charts reached their Done state
  /// A chart ended in its SafeStop state (a reaction that could not recover: the same failure
  /// again on the retry): motion stopped, the admittance holding; the run ends there.
  bool safe_stop = false;
  /// Why (safe_stop): the chart, the failure repeated, the state it repeated in, and the
  /// planner's reason for a plan failure.
  std::string stop_reason;
  Fidelity fidelity;
  double duration = 0.0;   ///< s of simulated time
  std::vector<report::EventRecord> events;
  /// Every state (full path) each chart entered, in order of first entry.
  std::vector<std::string> needle_states;
  std::vector<std::string> us_states;
  std::vector<NeedlePlacement> placements;
  /// Deployment switches, in order: "t needle needle_autonomous_planning".
  std::vector<std::string> switches;
  /// What happened, in order, one line each: task state changes of both charts ("needle >
  /// root.WaitCryoCycle", "us > root.MoveToSkin.Approach": a motion's internal steps folded into
  /// the motion), switches ("needle deployment > NAME", "probe deployment > NAME", "configuration
  /// > NAME") and every component's events ("NeedleMonitor: e_skin_touched").
  std::vector<std::string> log;
  /// Largest jump of the needle robot's commanded pose between two 1 ms steps [m].
  double max_command_step = 0.0;
  double max_command_step_at = 0.0;  ///< s, when it happened
  std::filesystem::path report;  ///< report.html, when a report folder was given
};

/// Loads, runs and reports one procedure. The runner is also the simulated cryoablation console:
/// when the needle chart enters WaitCryoCycle it starts a freeze (Patient.startFreeze; the
/// Patient thaws by itself after its freeze_duration).
/// @throws std::runtime_error with the deployer's message (file:line) when the files are wrong.
ProcedureResult runProcedure(const ProcedureOptions& options);

/// Registers the built-in packages the deployment file lists (cobra_motion, cobra_control,
/// cobra_coordination, cobra_planning, cobra_sim, cobra_puncturing), e.g. for a lint test.
void addPuncturingPackages(deploy::Configurator& configurator);

}  // namespace cobra::puncturing
