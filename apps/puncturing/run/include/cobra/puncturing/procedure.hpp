#pragma once
/// @file
/// One puncturing procedure in simulation (thesis ch. 4): the deployment file with both robots'
/// controllers, the simulated world and the scripted surgeon, run on the lockstep clock until both
/// task charts are done; then the run folder (event log, recorded signals, HTML report).
/// What `./do demo` runs and what the end-to-end tests drive.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "cobra/report/run_report.hpp"

namespace cobra::deploy {
class Configurator;
}

namespace cobra::puncturing {

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
  /// Called with one line per task state change and per switch (nullptr: quiet).
  std::function<void(const std::string&)> progress;
};

/// A needle at its target: where the tip ended and how far from the planned target.
struct NeedlePlacement {
  int needle = 0;
  double time = 0.0;      ///< s, when the needle chart left WaitCryoCycle (the tip held during the freeze)
  double error_mm = 0.0;  ///< mm, measured tip to planned target
};

struct ProcedureResult {
  bool completed = false;  ///< both charts reached their Done state
  double duration = 0.0;   ///< s of simulated time
  std::vector<report::EventRecord> events;
  /// Every state (full path) each chart entered, in order of first entry.
  std::vector<std::string> needle_states;
  std::vector<std::string> us_states;
  std::vector<NeedlePlacement> placements;
  /// Deployment switches, in order: "t needle needle_autonomous_planning".
  std::vector<std::string> switches;
  /// Largest jump of the needle robot's commanded pose between two 1 ms steps [m].
  double max_command_step = 0.0;
  std::filesystem::path report;  ///< report.html, when a report folder was given
};

/// Loads, runs and reports one procedure.
/// @throws std::runtime_error with the deployer's message (file:line) when the files are wrong.
ProcedureResult runProcedure(const ProcedureOptions& options);

/// Registers the built-in packages the deployment file lists (cobra_motion, cobra_control,
/// cobra_coordination, cobra_planning, cobra_sim, cobra_puncturing), e.g. for a lint test.
void addPuncturingPackages(deploy::Configurator& configurator);

}  // namespace cobra::puncturing
