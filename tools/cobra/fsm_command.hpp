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
/// Validates `file` and lists its states and transitions. Returns the exit status.
int checkFsm(const std::string& file);
/// Graphviz DOT of `chart`: composite states as nested clusters, connectors as points, edges
/// labelled with their events (and [pn], [guard]).
std::string chartDot(const statechart::Chart& chart, const std::string& title);

}  // namespace cobra::tools
