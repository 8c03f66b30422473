#pragma once
/// @file
/// The fault matrix (test/fault_matrix/README.md): one table (matrix.lua) of faults x tasks x
/// moments, read here into cells; each cell is one lockstep run of a task's application with the
/// fault played at the moment (a generated faults file), watched by the runner for a second after
/// its outcome is decided. A cell passes when the run completed or ended in the task's safe stop
/// with a failure event and a reason, the robots held (tool tips moving < 0.5 mm in the last
/// second), no non-finite command was written to a robot's command port, and the process neither
/// crashed nor hung. `cobra faults matrix` runs the cells in parallel processes and writes the
/// table (docs/fault_matrix.md); `cobra soak` repeats them in one process.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace cobra::fault_matrix {

/// A named instant of a task's procedure: `after` s after a chart enters a state.
struct Moment {
  std::string name;
  std::string state;   ///< "chart:path", as a faults file's `on = { state = }`
  double after = 0.0;  ///< s
  int line = 0;
};

/// A task: an application run on the lockstep clock.
struct Task {
  std::string name;
  std::filesystem::path app;                     ///< absolute
  std::vector<std::filesystem::path> scenarios;  ///< absolute; the first is the matrix's, the soak picks any ("" none)
  double time_limit = 300.0;                     ///< s simulated
  std::vector<Moment> moments;
  /// Ports watched holding (Frame: its position; double: m); empty: run.tracking's measured ports.
  std::vector<std::string> hold;
  /// Ports that carry the robots' commands (Frame, JntArray, double); empty: run.tracking's commanded.
  std::vector<std::string> commands;
  int line = 0;
};

/// A faults-file entry of a fault: its fields but `after` as Lua source ("call = \"X.y\", args = { 2 }").
struct Entry {
  std::string fields;
  double after = 0.0;        ///< s: after the moment (after its own trigger when it names one)
  bool own_trigger = false;  ///< it names its own `on` (played then, not at the cell's moment)
};

/// What a fault does to one task: faults-file entries (Lua source of each entry's action, played
/// at the cell's moment unless the entry names its own `on`), or "n/a" and why.
struct FaultForTask {
  std::string task;
  std::string na;       ///< non-empty: the fault does not apply, and why
  /// Known gaps: the cells expected to fail, and why; by moment ("" for every moment).
  std::vector<std::pair<std::string, std::string>> gaps;
  std::vector<Entry> entries;
  std::string before_lua;            ///< run before the entry file (e.g. a silent surgeon's script)
  std::vector<std::string> moments;  ///< the moments it is played at (empty: every moment of the task)
  int line = 0;
};

struct Fault {
  std::string name;
  std::string text;  ///< what it is, for the table
  std::vector<FaultForTask> tasks;  ///< one per task, in the table's task order
  int line = 0;
};

/// The fault whose cells play nothing: each task's procedure as it runs without a fault.
inline constexpr const char* kBaseline = "none";

struct Table {
  std::filesystem::path file;
  std::filesystem::path root;  ///< the repository (paths in the table are relative to it)
  std::vector<Task> tasks;
  std::vector<Fault> faults;
  const Task& task(const std::string& name) const;
};

/// Reads the table. @throws std::runtime_error "FILE:LINE: what is wrong; what was expected"
/// (an unknown task, moment or field, a fault saying nothing of a task, a Lua error).
Table readTable(const std::filesystem::path& file, const std::filesystem::path& root);

/// One run: a fault played on a task at a moment.
struct Cell {
  const Fault* fault = nullptr;
  const Task* task = nullptr;
  const FaultForTask* what = nullptr;
  const Moment* moment = nullptr;
  std::string id() const;  ///< "fault/task/moment"
  /// Why the table expects this cell to fail ("": it must pass).
  std::string gap() const;
};

/// The cells of the table (fault-major, in the table's order), of the tasks named (all when empty).
/// @throws std::runtime_error "unknown task 'x'; expected one of ..." for a name no task has.
std::vector<Cell> cells(const Table& table, const std::vector<std::string>& tasks = {});

/// The faults file a cell plays (Lua), naming the table's lines it comes from.
std::string faultsFileText(const Table& table, const Cell& cell);

/// What one run of a cell showed.
struct CellResult {
  std::string id;
  std::string outcome;    ///< run::toString(Outcome), or "crash", "hang", "error" (the process)
  std::string end_state;  ///< each chart's final state ("needle root.SafeStop, us root.SafeStop")
  std::string event;      ///< the last failure event heard ("NeedlePlanner: e_plan_failed"), "" none
  std::string reason;     ///< the run's reason (empty when completed)
  double hold_mm = 0.0;   ///< the largest tool-tip excursion over the last second [mm]
  int nan_commands = 0;   ///< steps a command port carried a non-finite value
  double duration = 0.0;  ///< s simulated
  double wall = 0.0;      ///< s of wall time
  std::vector<std::string> failures;  ///< what the cell breaks (empty: it passes)
  bool passed() const { return failures.empty(); }
};

/// How the robots must hold after a run's end: less than this over the last second [mm].
constexpr double kHoldMm = 0.5;
/// The window the hold is measured over [s] (the runner steps this long after the outcome).
constexpr double kHoldWindow = 1.0;

/// Runs one cell in this process (the soak's way). `faults_folder` receives the generated file.
CellResult runCell(const Table& table, const Cell& cell, const std::filesystem::path& faults_folder,
                   const std::filesystem::path& scenario = {});

/// Runs the cells in `jobs` child processes at a time; a child that outlives `wall_limit` s is
/// killed (outcome "hang"), one that dies by a signal is a "crash". `done` is told of each result.
std::vector<CellResult> runCells(const Table& table, const std::vector<Cell>& cells, int jobs, double wall_limit,
                                 const std::function<void(const CellResult&)>& done = {});

/// The expectation of a cell: it passes, unless the table declares a gap (then it fails).
/// "": as expected; else why not ("passes although the table declares a gap: ..."; "fails: ...").
std::string unexpected(const Cell& cell, const CellResult& result);

/// docs/fault_matrix.md for the table and the results of all its cells (in cells()' order).
std::string docText(const Table& table, const std::vector<Cell>& cells, const std::vector<CellResult>& results);
/// `doc` with what varies from run to run removed (the duration column): two docs of the same
/// cells' outcomes compare equal.
std::string withoutTimings(const std::string& doc);

/// The process's resident memory [kB] (VmRSS of /proc/self/status) and open file descriptors.
std::int64_t residentKb();
int openFds();

struct SoakOptions {
  double duration = 60.0;  ///< s of wall time (the run under way then finishes)
  std::uint64_t seed = 1;
  std::filesystem::path report;  ///< CSV, one row per run
  std::vector<std::string> tasks;  ///< empty: all
  std::function<void(const std::string&)> progress;
};
struct SoakSummary {
  int runs = 0;
  int passed = 0;
  std::int64_t rss_first_kb = 0, rss_last_kb = 0, rss_max_kb = 0;
  int fds_first = 0, fds_last = 0, fds_max = 0;
  /// Once every task has run (each loads its models once, so the memory after the first run says
  /// little): the run it happened at (0: never), VmRSS then and the most after it, kB.
  int warm_run = 0;
  std::int64_t rss_warm_kb = 0, rss_max_after_warm_kb = 0;
  std::string line;  ///< "soak: ..."
};
/// Repeats random runs (a task, one of its scenarios, its baseline cell one time in four, else a
/// random cell of the task's) until the
/// duration has passed, writing a CSV row per run (outcome, resident memory, open descriptors).
SoakSummary soak(const Table& table, const SoakOptions& options);

}  // namespace cobra::fault_matrix
