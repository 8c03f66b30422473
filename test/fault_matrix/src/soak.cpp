// cobra soak: random runs of the matrix's tasks in this one process for a given time (a leak of
// memory or descriptors shows as a trend), with the resident memory and open descriptors after
// each run in a CSV.

#include "cobra/fault_matrix/matrix.hpp"

#include <chrono>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <stdexcept>

#include <unistd.h>

namespace cobra::fault_matrix {

std::int64_t residentKb() {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stoll(line.substr(6));
  return -1;
}

int openFds() {
  int n = 0;
  std::error_code error;
  for (auto it = std::filesystem::directory_iterator("/proc/self/fd", error); !error && it != std::filesystem::directory_iterator();
       it.increment(error))
    ++n;
  return n - 1;  // the iterator's own descriptor
}

SoakSummary soak(const Table& table, const SoakOptions& options) {
  const std::vector<Cell> all = cells(table, options.tasks);
  std::vector<const Task*> tasks;
  for (const Task& t : table.tasks)
    if (options.tasks.empty() || std::find(options.tasks.begin(), options.tasks.end(), t.name) != options.tasks.end())
      tasks.push_back(&t);
  std::ofstream csv(options.report);
  if (!csv) throw std::runtime_error("--report " + options.report.string() + ": cannot write the file");
  csv << "wall [s],run,task,scenario,cell,outcome,verdict,VmRSS [kB],open fds\n";
  const std::filesystem::path faults = std::filesystem::temp_directory_path() / ("cobra_soak_" + std::to_string(::getpid()));
  std::mt19937_64 random(options.seed);
  SoakSummary s;
  std::map<std::string, int> outcomes;
  std::set<const Task*> ran;  // the tasks run so far, until every one has
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  while (s.runs == 0 || elapsed() < options.duration) {
    const Task& task = *tasks[random() % tasks.size()];
    const std::filesystem::path scenario = task.scenarios[random() % task.scenarios.size()];
    std::vector<const Cell*> of_task, baseline;
    for (const Cell& c : all)
      if (c.task == &task) (c.fault->name == kBaseline ? baseline : of_task).push_back(&c);
    // One run in four is the task's baseline (no fault) when the table has one; the others a
    // random cell of the task's.
    if (baseline.empty() && of_task.empty())
      throw std::runtime_error("cobra soak: task '" + task.name + "' has no cell to run (every fault n/a and no baseline)");
    const bool nominal = !baseline.empty() && (of_task.empty() || random() % 4 == 0);
    const Cell& cell = nominal ? *baseline[random() % baseline.size()] : *of_task[random() % of_task.size()];
    const CellResult r = runCell(table, cell, faults, scenario);
    const bool as_expected = unexpected(cell, r).empty();
    ++s.runs;
    s.passed += as_expected;
    ++outcomes[r.outcome];
    const std::int64_t rss = residentKb();
    const int fds = openFds();
    if (s.runs == 1) s.rss_first_kb = rss, s.fds_first = fds;
    s.rss_last_kb = rss, s.fds_last = fds;
    s.rss_max_kb = std::max(s.rss_max_kb, rss);
    s.fds_max = std::max(s.fds_max, fds);
    if (s.warm_run == 0 && ran.insert(&task).second && ran.size() == tasks.size())
      s.warm_run = s.runs, s.rss_warm_kb = rss;
    if (s.warm_run != 0) s.rss_max_after_warm_kb = std::max(s.rss_max_after_warm_kb, rss);
    char wall[32];
    std::snprintf(wall, sizeof wall, "%.3f", elapsed());
    csv << wall << "," << s.runs << "," << task.name << "," << scenario.filename().string() << "," << r.id << "," << r.outcome
        << "," << (as_expected ? "as expected" : "unexpected") << "," << rss << "," << fds << "\n";
    csv.flush();
    if (options.progress)
      options.progress(std::string(wall) + " s  run " + std::to_string(s.runs) + " " + r.id + ": " + r.outcome + ", VmRSS " +
                       std::to_string(rss) + " kB, " + std::to_string(fds) + " fds");
  }
  std::error_code ignored;
  std::filesystem::remove_all(faults, ignored);
  std::string text;
  for (const auto& [outcome, n] : outcomes) text += (text.empty() ? "" : ", ") + std::to_string(n) + " " + outcome;
  // The memory trend that means something: from the run after which every task had run once.
  char warm[192] = "";
  if (s.warm_run != 0 && s.rss_warm_kb > 0)
    std::snprintf(warm, sizeof warm, ", %lld kB once every task had run (run %d), at most %lld kB after it (%+.1f %%)",
                  static_cast<long long>(s.rss_warm_kb), s.warm_run, static_cast<long long>(s.rss_max_after_warm_kb),
                  100.0 * static_cast<double>(s.rss_max_after_warm_kb - s.rss_warm_kb) / static_cast<double>(s.rss_warm_kb));
  char line[768];
  std::snprintf(line, sizeof line,
                "soak: %d runs in %.1f s (%s), %d as expected; VmRSS %lld kB after the first run, %lld kB after the last "
                "(max %lld kB)%s; open file descriptors %d after the first run, %d after the last (max %d)%s",
                s.runs, elapsed(), text.c_str(), s.passed, static_cast<long long>(s.rss_first_kb),
                static_cast<long long>(s.rss_last_kb), static_cast<long long>(s.rss_max_kb), warm, s.fds_first, s.fds_last,
                s.fds_max, s.fds_first == s.fds_last && s.fds_max == s.fds_first ? ": constant" : ": CHANGED");
  s.line = line;
  return s;
}

}  // namespace cobra::fault_matrix
