// Running a cell of the fault matrix: one lockstep run of its task with the cell's generated faults
// file, watched by a RunObserver (the robots' positions over the last second, non-finite values on
// their command ports, the last failure event), the runner stepping on for kHoldWindow after the
// outcome is decided (RunOptions::watch_after_end). runCells runs cells in child processes.

#include "cobra/fault_matrix/matrix.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

#include "cobra/run/port_tap.hpp"
#include "cobra/run/run_spec.hpp"
#include "cobra/run/runner.hpp"

namespace cobra::fault_matrix {
namespace {

// The switch supervisors' refusals are failures whatever run.failures lists (as the runner's).
bool isFailure(const std::string& event, const std::vector<std::string>& failures) {
  if (event.rfind("e_configure_failed_", 0) == 0 || event.rfind("e_deploy_failed_", 0) == 0) return true;
  if (event.rfind("e_exception@", 0) == 0 || event.rfind("e_fatal_error@", 0) == 0) return true;
  return std::find(failures.begin(), failures.end(), event) != failures.end();
}

// Watches a run: each hold port's position every 10 ms (the last kHoldWindow s kept), every command
// port every step (a non-finite value counts), and the failure events heard.
class Watch final : public run::RunObserver {
 public:
  explicit Watch(const Task& task) : task_(task) {}

  void attach(const run::RunContext& run) override {
    failures_ = run.spec.failures;
    std::vector<std::string> hold = task_.hold, commands = task_.commands;
    for (const run::TrackingSpec& t : run.spec.tracking) {
      if (task_.hold.empty()) hold.push_back(t.measured);
      if (task_.commands.empty()) commands.push_back(t.commanded);
    }
    const std::string where = "fault matrix, task '" + task_.name + "'";
    for (const std::string& port : hold) {
      held_.push_back(Held{std::make_unique<run::NumericTap>(run.registry, port, where, "hold"), port, {}});
      // The window's samples (every 10 ms) and one before: stepping then allocates nothing.
      held_.back().samples.reserve(static_cast<std::size_t>(kHoldWindow / 0.01) + 16);
    }
    for (const std::string& port : commands)
      commands_.push_back(std::make_unique<run::NumericTap>(run.registry, port, where, "commands"));
  }

  void step(const run::StepView& now) override {
    for (auto& c : commands_) {
      c->read(row_);
      if (std::any_of(row_.begin(), row_.end(), [](double v) { return !std::isfinite(v); })) ++nan_commands_;
    }
    if (now.t + 1e-9 < next_sample_) return;
    next_sample_ = now.t + 0.01;
    for (Held& h : held_) {
      h.tap->read(row_);
      if (row_.empty()) continue;
      Sample s{now.t, row_[0], row_.size() > 1 ? row_[1] : 0.0, row_.size() > 2 ? row_[2] : 0.0};
      h.samples.push_back(s);
      // Keep the last window (and one sample before it).
      while (h.samples.size() > 2 && h.samples[1].t < now.t - kHoldWindow - 1e-9) h.samples.erase(h.samples.begin());
    }
  }

  void event(double, const std::string& source, const std::string& name) override {
    if (isFailure(name, failures_)) last_failure_ = source + ": " + name;
  }
  bool nextInput(std::size_t&) override { return false; }
  std::vector<std::string> finished(const run::RunResult&) override { return {}; }

  // The largest distance of a hold port's position, over the last window, from its position at
  // the window's start [mm] (m for a double port: its value in mm).
  double holdMm(double end) const {
    double worst = 0.0;
    for (const Held& h : held_) {
      const Sample* start = nullptr;
      for (const Sample& s : h.samples)
        if (s.t >= end - kHoldWindow - 1e-9) {
          if (start == nullptr) start = &s;
          worst = std::max(worst, std::hypot(s.x - start->x, s.y - start->y, s.z - start->z) * 1000.0);
        }
    }
    return worst;
  }
  int nanCommands() const { return nan_commands_; }
  const std::string& lastFailure() const { return last_failure_; }

 private:
  struct Sample {
    double t, x, y, z;
  };
  struct Held {
    std::unique_ptr<run::NumericTap> tap;
    std::string port;
    std::vector<Sample> samples;
  };
  const Task& task_;
  std::vector<std::string> failures_;
  std::vector<Held> held_;
  std::vector<std::unique_ptr<run::NumericTap>> commands_;
  std::vector<double> row_;
  double next_sample_ = 0.0;
  int nan_commands_ = 0;
  std::string last_failure_;
};

// `text` with every `prefix` removed (a temporary folder's path: the table is the same from run to run).
std::string without(std::string text, const std::string& prefix) {
  if (prefix.empty()) return text;
  for (std::size_t at = text.find(prefix); at != std::string::npos; at = text.find(prefix, at)) text.erase(at, prefix.size());
  return text;
}

CellResult runWith(const Task& task, std::string id, run::RunOptions o) {
  CellResult r;
  r.id = std::move(id);
  Watch watch(task);
  o.app = task.app;
  o.time_limit = task.time_limit;
  o.watch_after_end = kHoldWindow;
  o.observer = &watch;
  const auto start = std::chrono::steady_clock::now();
  try {
    const run::RunResult result = run::runApp(o);
    r.outcome = run::toString(result.outcome);
    // The generated faults file is named by its name alone (its folder is temporary).
    const std::string folder = o.faults_file.empty() ? std::string() : o.faults_file.parent_path().string() + "/";
    r.reason = without(result.reason, folder);
    for (const auto& [chart, state] : result.final_states) r.end_state += (r.end_state.empty() ? "" : ", ") + chart + " " + state;
    r.duration = result.duration;
    r.hold_mm = watch.holdMm(result.duration);
    r.nan_commands = watch.nanCommands();
    r.event = watch.lastFailure();
    if (result.outcome != run::Outcome::Completed && result.outcome != run::Outcome::SafeStop)
      r.failures.push_back("ended " + r.outcome + ", neither completed nor in the safe stop");
    if (result.outcome == run::Outcome::SafeStop && (r.event.empty() || r.reason.find("(no failure event seen)") != std::string::npos))
      r.failures.push_back("a safe stop without its failure event");
    if (r.hold_mm >= kHoldMm) {
      char text[96];
      std::snprintf(text, sizeof text, "the robots moved %.2f mm in the last second (< %.1f mm expected)", r.hold_mm, kHoldMm);
      r.failures.push_back(text);
    }
    if (r.nan_commands > 0) r.failures.push_back(std::to_string(r.nan_commands) + " steps with a non-finite robot command");
  } catch (const std::exception& e) {
    r.outcome = "error";
    r.reason = without(e.what(), o.faults_file.empty() ? std::string() : o.faults_file.parent_path().string() + "/");
    r.failures.push_back(std::string("the run did not start: ") + e.what());
  }
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

// One result as text lines "key=value" (newlines in values as \n), for a child's result file.
std::string encode(const CellResult& r) {
  const auto esc = [](std::string v) {
    std::string out;
    for (char c : v) out += c == '\n' ? std::string("\\n") : c == '\\' ? std::string("\\\\") : std::string(1, c);
    return out;
  };
  std::ostringstream out;
  out.precision(17);
  out << "id=" << esc(r.id) << "\noutcome=" << esc(r.outcome) << "\nend_state=" << esc(r.end_state) << "\nevent=" << esc(r.event)
      << "\nreason=" << esc(r.reason) << "\nhold_mm=" << r.hold_mm << "\nnan_commands=" << r.nan_commands
      << "\nduration=" << r.duration << "\nwall=" << r.wall << "\n";
  for (const std::string& f : r.failures) out << "failure=" << esc(f) << "\n";
  return out.str();
}

CellResult decode(const std::string& text) {
  CellResult r;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = line.substr(0, eq);
    std::string v;
    for (std::size_t i = eq + 1; i < line.size(); ++i)
      if (line[i] == '\\' && i + 1 < line.size()) v += line[++i] == 'n' ? '\n' : line[i];
      else v += line[i];
    if (key == "id") r.id = v;
    else if (key == "outcome") r.outcome = v;
    else if (key == "end_state") r.end_state = v;
    else if (key == "event") r.event = v;
    else if (key == "reason") r.reason = v;
    else if (key == "hold_mm") r.hold_mm = std::stod(v);
    else if (key == "nan_commands") r.nan_commands = std::stoi(v);
    else if (key == "duration") r.duration = std::stod(v);
    else if (key == "wall") r.wall = std::stod(v);
    else if (key == "failure") r.failures.push_back(v);
  }
  return r;
}

}  // namespace

CellResult runCell(const Table& table, const Cell& cell, const std::filesystem::path& faults_folder,
                   const std::filesystem::path& scenario) {
  std::string name = cell.id();
  std::replace(name.begin(), name.end(), '/', '.');
  const std::filesystem::path faults = faults_folder / (name + ".lua");
  std::filesystem::create_directories(faults_folder);
  std::ofstream(faults) << faultsFileText(table, cell);
  run::RunOptions o;
  o.scenario = scenario.empty() ? cell.task->scenarios.front() : scenario;
  o.faults_file = faults;
  o.before_lua = cell.what->before_lua;
  return runWith(*cell.task, cell.id(), o);
}

std::vector<CellResult> runCells(const Table& table, const std::vector<Cell>& cells, int jobs, double wall_limit,
                                 const std::function<void(const CellResult&)>& done) {
  std::vector<CellResult> results(cells.size());
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("cobra_fault_matrix_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  struct Child {
    pid_t pid;
    std::size_t cell;
    std::chrono::steady_clock::time_point start;
  };
  std::vector<Child> running;
  std::size_t next = 0;
  const auto resultFile = [&](std::size_t i) { return folder / ("result_" + std::to_string(i) + ".txt"); };
  const auto finish = [&](const Child& c, int status) {
    CellResult& r = results[c.cell];
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - c.start).count();
    std::ifstream in(resultFile(c.cell));
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && !text.empty()) {
      r = decode(text);
    } else {
      r.id = cells[c.cell].id();
      r.wall = wall;
      r.outcome = WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL && wall >= wall_limit ? "hang" : "crash";
      r.reason = r.outcome == "hang" ? "still running after " + std::to_string(static_cast<int>(wall_limit)) + " s of wall time"
                 : WIFSIGNALED(status)   ? std::string("killed by signal ") + strsignal(WTERMSIG(status))
                                         : "exit status " + std::to_string(WEXITSTATUS(status)) + " without a result";
      r.failures.push_back("the process " + (r.outcome == "hang" ? std::string("hung: ") : std::string("crashed: ")) + r.reason);
    }
    if (done) done(r);
  };
  while (next < cells.size() || !running.empty()) {
    while (next < cells.size() && static_cast<int>(running.size()) < std::max(jobs, 1)) {
      std::fflush(nullptr);
      const pid_t pid = ::fork();
      if (pid < 0) throw std::runtime_error(std::string("cobra faults: fork failed: ") + std::strerror(errno));
      if (pid == 0) {
        int code = 0;
        try {
          const CellResult r = runCell(table, cells[next], folder / "faults");
          std::ofstream(resultFile(next)) << encode(r);
        } catch (...) {
          code = 1;
        }
        std::fflush(nullptr);
        ::_exit(code);
      }
      running.push_back(Child{pid, next++, std::chrono::steady_clock::now()});
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    for (auto c = running.begin(); c != running.end();) {
      int status = 0;
      const pid_t got = ::waitpid(c->pid, &status, WNOHANG);
      if (got == 0) {
        if (std::chrono::duration<double>(std::chrono::steady_clock::now() - c->start).count() >= wall_limit) ::kill(c->pid, SIGKILL);
        ++c;
        continue;
      }
      finish(*c, status);
      c = running.erase(c);
    }
  }
  std::error_code ignored;
  std::filesystem::remove_all(folder, ignored);
  return results;
}

std::string unexpected(const Cell& cell, const CellResult& result) {
  std::string failures;
  for (const std::string& f : result.failures) failures += (failures.empty() ? "" : "; ") + f;
  const std::string gap = cell.gap();
  if (gap.empty()) return result.passed() ? "" : "fails: " + failures;
  return result.passed() ? "passes although the table declares a gap (" + gap + "): remove the gap" : "";
}

}  // namespace cobra::fault_matrix
