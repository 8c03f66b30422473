#include "faults_command.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "cobra/fault_matrix/matrix.hpp"

namespace cobra::tools {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The first line where two texts differ, for the message of a stale doc.
std::string firstDifference(const std::string& a, const std::string& b) {
  std::istringstream x(a), y(b);
  std::string l, m;
  for (int line = 1;; ++line) {
    const bool more_x = static_cast<bool>(std::getline(x, l)), more_y = static_cast<bool>(std::getline(y, m));
    if (!more_x && !more_y) return "";
    if (l != m || more_x != more_y)
      return "line " + std::to_string(line) + ": committed \"" + (more_x ? l : "(end)") + "\", now \"" + (more_y ? m : "(end)") + "\"";
  }
}

}  // namespace

FaultsCommands::FaultsCommands(CLI::App& app) {
  CLI::App* faults = app.add_subcommand("faults", "the fault matrix: every fault x task x moment, run and tabled");
  faults->require_subcommand(1);
  matrix_ = faults->add_subcommand("matrix", "run the matrix's cells (lockstep, in parallel processes) and write its table");
  matrix_->add_option("--table", table_, "the matrix's table (default test/fault_matrix/matrix.lua)");
  matrix_->add_option("--root", root_, "the repository the table's paths are relative to (default .)");
  matrix_->add_option("--tasks", tasks_, "only these tasks (default all)")->delimiter(',');
  matrix_->add_option("--cells", only_, "only the cells whose id (fault/task/moment) starts with one of these")->delimiter(',');
  matrix_->add_option("--jobs", jobs_, "cells run at a time, each in its own process (default 2)")->check(CLI::PositiveNumber);
  matrix_->add_option("--cell-time", cell_time_, "s of wall time after which a cell's process counts as hung and is killed "
                                                 "(default 600)")->check(CLI::PositiveNumber);
  matrix_->add_option("--doc", doc_, "write the table (Markdown) there, e.g. docs/fault_matrix.md");
  matrix_->add_option("--check-doc", check_doc_, "fail when this committed table differs from the results (durations apart)");
  matrix_->footer("example: cobra faults matrix --jobs 2 --doc docs/fault_matrix.md\n"
                  "exit status 0 when every cell ends as the table expects (completed or its safe stop, robots holding, "
                  "no non-finite command; a declared gap fails), else 1");
  soak_ = app.add_subcommand("soak", "repeat random procedures and faults of the matrix in one process for a given time");
  soak_->add_option("--duration", duration_, "s of wall time (the run under way then finishes)")->required()->check(CLI::PositiveNumber);
  soak_->add_option("--seed", seed_, "seed of the random choices (default 1)");
  soak_->add_option("--report", report_, "CSV: one row per run (outcome, VmRSS, open descriptors)")->required();
  soak_->add_option("--table", table_, "the matrix's table (default test/fault_matrix/matrix.lua)");
  soak_->add_option("--root", root_, "the repository the table's paths are relative to (default .)");
  soak_->add_option("--tasks", tasks_, "only these tasks (default all)")->delimiter(',');
  soak_->footer("example: cobra soak --duration 3600 --seed 7 --report build/soak.csv\n"
                "exit status 0 when it ran and the open descriptors stayed constant, else 1");
}

bool FaultsCommands::chosen() const { return *matrix_ || *soak_; }

int FaultsCommands::run() const { return *matrix_ ? runMatrix() : runSoak(); }

int FaultsCommands::runMatrix() const {
  const fault_matrix::Table table = fault_matrix::readTable(table_, std::filesystem::absolute(root_).lexically_normal());
  std::vector<fault_matrix::Cell> cells = fault_matrix::cells(table, tasks_);
  if (!only_.empty()) {
    std::erase_if(cells, [&](const fault_matrix::Cell& c) {
      return std::none_of(only_.begin(), only_.end(), [&](const std::string& o) { return c.id().rfind(o, 0) == 0; });
    });
    if (cells.empty()) throw std::runtime_error("--cells: no cell's id starts with any of them (ids are fault/task/moment)");
  }
  std::printf("fault matrix: %zu cells, %d at a time\n", cells.size(), jobs_);
  std::fflush(stdout);
  int done = 0;
  const std::vector<fault_matrix::CellResult> results =
      fault_matrix::runCells(table, cells, jobs_, cell_time_, [&](const fault_matrix::CellResult& r) {
        std::printf("[%d/%zu] %s: %s%s (%.1f s simulated, %.1f s wall, hold %.3f mm)\n", ++done, cells.size(), r.id.c_str(),
                    r.outcome.c_str(), r.passed() ? "" : " FAILED", r.duration, r.wall, r.hold_mm);
        for (const std::string& f : r.failures) std::printf("    %s\n", f.c_str());
        std::fflush(stdout);
      });
  int unexpected = 0;
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (const std::string why = fault_matrix::unexpected(cells[i], results[i]); !why.empty()) {
      std::printf("UNEXPECTED %s: %s\n", cells[i].id().c_str(), why.c_str());
      ++unexpected;
    }
  const std::string doc = fault_matrix::docText(table, cells, results);
  if (!doc_.empty()) {
    std::ofstream(doc_) << doc;
    std::printf("wrote %s\n", doc_.c_str());
  }
  int stale = 0;
  if (!check_doc_.empty()) {
    const std::string difference =
        firstDifference(fault_matrix::withoutTimings(readFile(check_doc_)), fault_matrix::withoutTimings(doc));
    if (!difference.empty()) {
      std::printf("STALE %s: the committed table differs from these results (%s); write it again with --doc %s\n",
                  check_doc_.c_str(), difference.c_str(), check_doc_.c_str());
      stale = 1;
    } else {
      std::printf("%s is up to date\n", check_doc_.c_str());
    }
  }
  std::printf("fault matrix: %zu cells, %d unexpected\n", cells.size(), unexpected);
  return unexpected > 0 || stale ? 1 : 0;
}

int FaultsCommands::runSoak() const {
  const fault_matrix::Table table = fault_matrix::readTable(table_, std::filesystem::absolute(root_).lexically_normal());
  fault_matrix::SoakOptions options;
  options.duration = duration_;
  options.seed = seed_;
  options.report = report_;
  options.tasks = tasks_;
  options.progress = [](const std::string& line) {
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  };
  const fault_matrix::SoakSummary s = fault_matrix::soak(table, options);
  std::printf("%s\nreport: %s\n", s.line.c_str(), report_.c_str());
  return s.runs > 0 && s.fds_first == s.fds_last && s.fds_max == s.fds_first ? 0 : 1;
}

}  // namespace cobra::tools
