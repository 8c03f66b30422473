#pragma once
/// @file
/// The report of one run of an application as an HTML page: a timeline of every chart's states,
/// plots and a summary, self-contained (inline SVG, no script, no download). It renders the
/// runner's report data (cobra/run/report.hpp: RunReport, EventRecord, StateInterval, Figure),
/// and registers itself with the runner (registerHtmlReport; the `cobra` tool and the
/// `cobra::run` CMake target do it): cobra::run sits below tools/ and knows no renderer.

#include <filesystem>
#include <string>
#include <vector>

#include "cobra/plot/svg_plot.hpp"
#include "cobra/run/report.hpp"

namespace cobra::report {

using run::eventLogCsv;

/// A Gantt-like SVG: one lane per chart, one box per interval, labelled with the state's leaf
/// name when it fits (the full name is the box's tooltip).
std::string timelineSvg(const std::vector<StateInterval>& timeline, int width = 900);

/// The self-contained HTML page of `report`.
std::string toHtml(const RunReport& report);

/// Writes `report.html` into `folder` (which exists). @return its path.
/// @throws std::runtime_error naming the file it cannot write.
std::filesystem::path writeHtml(const std::filesystem::path& folder, const RunReport& report);

/// Makes the runner write report.html into every run folder (run::ObserverRegistry's report
/// writer "html"). Registering again does nothing.
void registerHtmlReport();

/// Writes `events.csv` and `report.html` into `folder` (created if needed).
/// @return the path of report.html. @throws std::runtime_error naming the file it cannot write.
std::filesystem::path writeRunFolder(const std::filesystem::path& folder, const RunReport& report);

}  // namespace cobra::report
