// The fault matrix's table (test/fault_matrix/matrix.lua and small bad tables written here): its
// tasks, faults and cells, the faults file a cell plays, the doc's rows, and each error of a bad
// table as its one line naming FILE:LINE and what was expected. Runs nothing (fault_matrix_runs
// runs the cells through `cobra faults matrix`).

#include "cobra/fault_matrix/matrix.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include "cobra/test_support/test_support.hpp"

namespace cobra::fault_matrix {
namespace {

const std::filesystem::path kRoot = COBRA_SOURCE_DIR;
const std::filesystem::path kTable = kRoot / "test" / "fault_matrix" / "matrix.lua";

// A table written to a temporary file; the error its reading throws ("" when none).
std::string errorOf(const std::string& text) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("cobra_matrix_" + std::to_string(::getpid()) + ".lua");
  std::ofstream(file) << text;
  try {
    readTable(file, kRoot);
  } catch (const std::exception& e) {
    std::string message = e.what();
    const std::string prefix = file.string() + ":";
    return message.rfind(prefix, 0) == 0 ? "FILE:" + message.substr(prefix.size()) : message;
  }
  return "";
}

constexpr const char* kTask = R"lua(
task "door" {
  app = "apps/door",
  moments = {
    { "turn", state = "door:root.opening.turn", after = 0.3 },
  },
}
)lua";

TEST(FaultMatrixTable, TheCommittedTableHasEveryTaskAndFaultAndItsCellsSkipWhatDoesNotApply) {
  const Table table = readTable(kTable, kRoot);
  std::vector<std::string> tasks;
  for (const Task& t : table.tasks) tasks.push_back(t.name);
  EXPECT_EQ(tasks, (std::vector<std::string>{"puncturing", "suturing", "puma260", "door"}));
  EXPECT_EQ(table.task("puncturing").app, kRoot / "apps" / "puncturing");
  EXPECT_EQ(table.task("puncturing").scenarios.size(), 2u);
  ASSERT_GE(table.faults.size(), 10u);
  const std::vector<Cell> all = cells(table);
  // peer_lost applies to no task of one process; drive_fault to the Puma 260 only (two moments).
  EXPECT_EQ(std::count_if(all.begin(), all.end(), [](const Cell& c) { return c.fault->name == "peer_lost"; }), 0);
  EXPECT_EQ(std::count_if(all.begin(), all.end(), [](const Cell& c) { return c.fault->name == "drive_fault"; }), 2);
  const std::vector<Cell> door = cells(table, {"door"});
  EXPECT_TRUE(std::all_of(door.begin(), door.end(), [](const Cell& c) { return c.task->name == "door"; }));
  EXPECT_FALSE(door.empty());
  try {
    cells(table, {"dor"});
    ADD_FAILURE() << "an unknown task was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "unknown task 'dor'; expected one of puncturing, suturing, puma260, door");
  }
}

TEST(FaultMatrixTable, ACellsFaultsFilePlaysItsEntriesAtTheMomentAndKeepsAnEntrysOwnTrigger) {
  const Table table = readTable(kTable, kRoot);
  for (const Cell& c : cells(table, {"suturing"})) {
    if (c.id() != "planner_failure/suturing/pull") continue;
    const std::string text = faultsFileText(table, c);
    EXPECT_CONTAINS(text, "-- The fault matrix's cell planner_failure/suturing/pull: " + kTable.string() + ":");
    EXPECT_CONTAINS(text, "  { on = { state = \"suture:root.AutonomousMode.PullThread\" }, after = 0.5, lua = ");
    EXPECT_CONTAINS(text, "  { args = { \"e_recover\" }, call = \"Surgeon.say\", on = { state = \"suture:root.WaitReaction\" }, "
                          "after = 1 },");
    return;
  }
  ADD_FAILURE() << "no cell planner_failure/suturing/pull";
}

TEST(FaultMatrixTable, NaNAndInfinityInAnEntryAreWrittenAsLuaCanReadThem) {
  const std::string table = std::string(kTask) + R"lua(
fault "f" { text = "t", door = { { write = { port = "TorqueCmd.out", value = 0/0 } }, { set = { property = "A.b", value = -math.huge } } } }
)lua";
  const std::filesystem::path file = std::filesystem::temp_directory_path() / ("cobra_matrix_nan_" + std::to_string(::getpid()) + ".lua");
  std::ofstream(file) << table;
  const Table t = readTable(file, kRoot);
  const std::vector<Cell> c = cells(t);
  ASSERT_EQ(c.size(), 1u);
  const std::string text = faultsFileText(t, c[0]);
  EXPECT_CONTAINS(text, "write = { port = \"TorqueCmd.out\", value = 0/0 } },");
  EXPECT_CONTAINS(text, "set = { property = \"A.b\", value = -math.huge } },");
}

TEST(FaultMatrixTable, AnUnknownTaskInAFaultIsOneLineNamingItsLineAndTheTasks) {
  EXPECT_EQ(errorOf(std::string(kTask) + "fault \"f\" {\n  text = \"t\",\n  dor = na \"x\",\n}\n"),
            "FILE:10: fault 'f': unknown task 'dor' (a fault's fields are `text` and its tasks); did you mean 'door'? "
            "known tasks: door");
}

TEST(FaultMatrixTable, AnUnknownMomentIsOneLineNamingItsLineAndTheTasksMoments) {
  EXPECT_EQ(errorOf(std::string(kTask) + "fault \"f\" {\n  text = \"t\",\n  door = { { throw = \"Door\" }, moments = { \"trun\" } },\n}\n"),
            "FILE:10: fault 'f', task 'door': unknown moment 'trun'; did you mean 'turn'? known moments: turn");
}

TEST(FaultMatrixTable, AFaultSayingNothingOfATaskIsRefused) {
  EXPECT_EQ(errorOf(std::string(kTask) + "fault \"f\" { text = \"t\" }\n"),
            "FILE:8: fault 'f' says nothing of task 'door'; give its entries or door = na \"why it does not apply\"");
}

TEST(FaultMatrixTable, AnUnknownFieldOfATaskOrOfAFaultsTaskIsRefused) {
  EXPECT_EQ(errorOf("task \"door\" {\n  app = \"apps/door\",\n  moment = {},\n}\n"),
            "FILE:3: task 'door': unknown field 'moment'; did you mean 'moments'? known fields: app, scenarios, "
            "time_limit, moments, hold, commands");
  EXPECT_EQ(errorOf(std::string(kTask) + "fault \"f\" {\n  text = \"t\",\n  door = { { throw = \"Door\" }, gaps = \"x\" },\n}\n"),
            "FILE:10: fault 'f', task 'door': unknown field 'gaps'; did you mean 'gap'? known fields: na, gap, "
            "before, moments");
}

TEST(FaultMatrixTable, AMomentWithoutAChartStateAndATaskWithoutMomentsAreRefused) {
  EXPECT_EQ(errorOf("task \"door\" {\n  app = \"apps/door\",\n  moments = {\n    { \"turn\", state = \"root.opening\" },\n  },\n}\n"),
            "FILE:4: task 'door', moment 'turn': needs `state = \"chart:path\"` (the chart of run.charts and a state path)");
  EXPECT_EQ(errorOf("task \"door\" { app = \"apps/door\", moments = {} }\n"), "FILE:1: task 'door': needs at least one moment");
}

TEST(FaultMatrixTable, AGapOfAnUnknownMomentIsRefused) {
  EXPECT_EQ(errorOf(std::string(kTask) + "fault \"f\" {\n  text = \"t\",\n  door = { { throw = \"Door\" }, gap = { trun = \"x\" } },\n}\n"),
            "FILE:10: fault 'f', task 'door': unknown moment 'trun'; did you mean 'turn'? known moments: turn");
}

TEST(FaultMatrixTable, AFaultWithNeitherEntriesNorNaAndOneWithBothAreRefused) {
  EXPECT_EQ(errorOf(std::string(kTask) + "fault \"f\" {\n  text = \"t\",\n  door = {},\n}\n"),
            "FILE:10: fault 'f', task 'door': no entry: give the faults-file entries to play, or na \"why it does not apply\"");
  EXPECT_EQ(errorOf(std::string(kTask) + "fault \"f\" {\n  text = \"t\",\n  door = { { throw = \"Door\" }, na = \"x\" },\n}\n"),
            "FILE:10: fault 'f', task 'door': both entries and na: give one");
}

TEST(FaultMatrixTable, ALuaErrorNamesItsLine) {
  EXPECT_EQ(errorOf("task \"door\" {\n  app = = 1,\n}\n"), "FILE:2: unexpected symbol near '='");
}

TEST(FaultMatrixDoc, TheDocHasARowPerCellTheNotApplicableWithWhyAndTheGapsAndIgnoresDurations) {
  Table table = readTable(kTable, kRoot);
  // A gap declared here (the committed table's own come and go as they are fixed).
  const auto ik = std::find_if(table.faults.begin(), table.faults.end(), [](const Fault& f) { return f.name == "ik_discontinuity"; });
  ASSERT_NE(ik, table.faults.end());
  const auto puma = std::find_if(ik->tasks.begin(), ik->tasks.end(), [](const FaultForTask& t) { return t.task == "puma260"; });
  ASSERT_NE(puma, ik->tasks.end());
  puma->gaps.emplace_back("surface", "a gap this test declares");
  const std::vector<Cell> all = cells(table);
  std::vector<CellResult> results(all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    results[i].id = all[i].id();
    results[i].outcome = "safe stop";
    results[i].reason = "a | b";
    results[i].duration = 12.5;
  }
  const auto gap = std::find_if(all.begin(), all.end(), [](const Cell& c) { return c.id() == "ik_discontinuity/puma260/surface"; });
  ASSERT_NE(gap, all.end());
  results[static_cast<std::size_t>(gap - all.begin())].failures.push_back(
      "the robots moved 3.00 mm in the last second (< 0.5 mm expected)");
  const std::string doc = docText(table, all, results);
  EXPECT_CONTAINS(doc, "| ik_discontinuity | puma260 | surface | gap: the robots moved 3.00 mm in the last second (< 0.5 mm "
                       "expected) | safe stop | - | - | a \\| b | 0.000 | 12.500 s |\n");
  EXPECT_CONTAINS(doc, "| drive_fault | door | the simulated door has no drives |\n");
  EXPECT_CONTAINS(doc, "| a lost peer host | n/a | n/a | n/a | n/a |\n");
  EXPECT_CONTAINS(doc, "| none | puncturing | approach | ok | safe stop | - | - | a \\| b | 0.000 | 12.500 s |\n");
  EXPECT_CONTAINS(doc, "- ik_discontinuity / puma260 / surface: a gap this test declares");
  results[1].duration = 99.0;
  EXPECT_NE(docText(table, all, results), doc);
  EXPECT_EQ(withoutTimings(docText(table, all, results)), withoutTimings(doc));
  results[1].outcome = "completed";
  EXPECT_NE(withoutTimings(docText(table, all, results)), withoutTimings(doc));
}

TEST(FaultMatrixProcess, ResidentMemoryAndOpenDescriptorsAreRead) {
  EXPECT_GT(residentKb(), 0);
  const int before = openFds();
  EXPECT_GE(before, 3);  // stdin, stdout, stderr
  {
    std::ifstream open(kTable);
    EXPECT_EQ(openFds(), before + 1);
  }
  EXPECT_EQ(openFds(), before);
}

}  // namespace
}  // namespace cobra::fault_matrix
