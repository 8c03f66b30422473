#pragma once
// `cobra fsm run|check|graph FILE`: rFSM charts from the command line.

#include <string>
#include <vector>

#include "cobra/statechart/chart.hpp"

namespace cobra::tools {

/// Loads `file`, runs it until idle and prints the active leaf; then for each token of `events`
/// (whitespace-separated; "-" sends none) sends it, runs until idle and prints the active leaf.
/// Nothing else goes to stdout (Lua's print is sent to stderr). A callback that fails (a Lua
/// error, or past 1 s of CPU time after one event: an endless loop) ends the run there, its
/// file:line on stderr: exit status 1. Returns the exit status.
int runFsm(const std::string& file, const std::string& events);
/// Runs task chart `file` as its Supervisor would, on a simulated clock from 0 to `until` s in
/// steps of `step` s (so e_after(...) transitions fire): `emit`, `raise`, `applyDeployment` and
/// `applyConfiguration` are defined, every peer (a global named like a component) is a stand-in that
/// says each call, and the chart's own helpers and cobra's charts (task_steps.lua) are found as a
/// Supervisor finds them. `events`: "NAME" (sent at 0 s) or "NAME@SECONDS". Prints one line per
/// state entered, event sent, event emitted and peer called, each with its time. Returns the exit
/// status (1: a callback failed, named on stderr).
/// @throws std::runtime_error on a bad --until, --step or --events.
int runFsmUntil(const std::string& file, double until, double step, const std::string& events);
/// Validates `file` and lists its states and transitions. Returns the exit status.
int checkFsm(const std::string& file);
/// Graphviz DOT of `chart`: composite states as nested clusters, connectors as points, edges
/// labelled with their events (and [pn], [guard]).
std::string chartDot(const statechart::Chart& chart, const std::string& title);

}  // namespace cobra::tools
