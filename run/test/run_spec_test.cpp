// Reading the `run` table of an entry file (run_spec.hpp: readRunSpec): every field into its
// struct, and a table that lacks what the runner needs is one line with file:line, the path in
// the table and what is expected. (Faults files: faults_test.cpp.)

#include "cobra/run/run_spec.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "cobra/script/lua_state.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::run {
namespace {

using test_support::messageOf;

/// The entry file of the running test: one per test and process (ctest runs the tests of this
/// file in parallel processes, which must not write each other's files).
std::string file(const std::string& name = "entry.lua") {
  const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  return (std::filesystem::temp_directory_path() /
          ("cobra_run_spec_" + test + "_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

/// Writes `text` as an entry file, runs it and reads its `run` table.
RunSpec read(const std::string& text, const std::string& name = "entry.lua") {
  const std::string path = file(name);
  std::ofstream(path) << text;
  script::LuaState lua;
  lua.runFile(path);
  return readRunSpec(lua.get(), path);
}

TEST(RunSpec, ReadsEveryFieldOfTheTable) {
  const RunSpec spec = read(R"(
run = {
  title = "T",
  charts = { { name = "a", supervisor = "ASup", done = "root.Done", safe_stop = "root.Stop", scope = "arm",
               sources = { "A", "B" } } },
  fold = { "Moving" },
  failures = { "e_x" },
  explain = { e_x = "why" },
  step = 0.002,
  actions = { { on = { event = "e_go", source = "B" }, after = 1.5, call = "C.op", args = { 1, 2 } } },
  record = { period = 0.02, ports = { "C.out", "D.pose" } },
  plots = { { title = "P", unit = "m", x = "C.out", x_unit = "s", series = { "D.pose.z" } } },
  summary = { { name = "S", unit = "mm", scale = 1000, distance = { "D.pose", "E.pose" }, on_leave = "a:root.Wait",
                of = "E.count" },
              { name = "N", count = { "e_x", "e_y" } } },
  tracking = { { name = "tool", commanded = "C.cmd", measured = "D.pose", joints = "D.q", max_velocity = "D.vmax",
                 chart = "a", accept_mm = 3, counts_while = { scope = "arm", deployments = { "auto" } } } },
  clearance = { port = "E.d", threshold = 0.005, contacts = { { name = "c", port = "E.c" } },
                pauses = { { name = "p", chart = "a", from = { "In" }, to = { "Out" } } } },
}
)");
  EXPECT_EQ(spec.title, "T");
  ASSERT_EQ(spec.charts.size(), 1u);
  EXPECT_EQ(spec.charts[0].supervisor, "ASup");
  EXPECT_EQ(spec.charts[0].safe_stop, "root.Stop");
  EXPECT_EQ(spec.charts[0].scope, "arm");
  EXPECT_EQ(spec.charts[0].sources, (std::vector<std::string>{"A", "B"}));
  EXPECT_EQ(spec.charts[0].where.line, 4);
  EXPECT_EQ(spec.explain.at("e_x"), "why");
  EXPECT_EQ(spec.step, 0.002);
  ASSERT_EQ(spec.actions.size(), 1u);
  EXPECT_EQ(spec.actions[0].on.kind, Trigger::Kind::Event);
  EXPECT_EQ(spec.actions[0].on.source, "B");
  EXPECT_EQ(spec.actions[0].after, 1.5);
  EXPECT_TRUE(spec.actions[0].repeat);  // actions repeat unless told; faults fire once
  EXPECT_EQ(spec.actions[0].component, "C");
  EXPECT_EQ(spec.actions[0].member, "op");
  EXPECT_EQ(spec.actions[0].where.line, 10);
  EXPECT_EQ(spec.record.period, 0.02);
  EXPECT_EQ(spec.record.ports[1].first, "D.pose");
  EXPECT_EQ(spec.plots[0].x, "C.out");
  EXPECT_EQ(spec.plots[0].where.line, 12);
  EXPECT_EQ(spec.summary[0].kind, SummarySpec::Kind::Distance);
  EXPECT_TRUE(spec.summary[0].leave);
  EXPECT_EQ(spec.summary[0].chart, "a");
  EXPECT_EQ(spec.summary[0].state, "root.Wait");
  EXPECT_EQ(spec.summary[1].events, (std::vector<std::string>{"e_x", "e_y"}));
  EXPECT_EQ(spec.tracking[0].accept_mm, 3.0);
  EXPECT_EQ(spec.tracking[0].accept_deg, 1.0);
  EXPECT_EQ(spec.tracking[0].counts_while, (std::vector<std::string>{"auto"}));
  EXPECT_TRUE(spec.clearance.declared);
  EXPECT_EQ(spec.clearance.threshold, 0.005);
  EXPECT_EQ(spec.clearance.pauses[0].to, (std::vector<std::string>{"Out"}));
}

TEST(RunSpec, ReadsTheClearancePerPairAndTheExpectedEventsOfACount) {
  const RunSpec spec = read(R"(
run = {
  charts = { { name = "a", supervisor = "ASup", done = "root.Done" } },
  summary = { { name = "faults", count = { "e_x", "e_lost" },
                expected = { { event = "e_lost", during = "a:root.Removing" } } } },
  clearance = { port = "E.d", threshold = 0.005,
                pairs = "E.pairDistances", pair_names = "E.clearancePairs" },
}
)");
  ASSERT_EQ(spec.summary[0].expected.size(), 1u);
  EXPECT_EQ(spec.summary[0].expected[0].event, "e_lost");
  EXPECT_EQ(spec.summary[0].expected[0].chart, "a");
  EXPECT_EQ(spec.summary[0].expected[0].state, "root.Removing");
  EXPECT_EQ(spec.clearance.pairs, "E.pairDistances");
  EXPECT_EQ(spec.clearance.pair_names, "E.clearancePairs");
  EXPECT_EQ(spec.clearance.pairs_where.line, 7);
}

TEST(RunSpec, ABadClearancePairOrExpectedEventIsOneLineWithFileLineAndWhatIsExpected) {
  EXPECT_CONTAINS(messageOf([] {
                    read("run = {\n  charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n"
                         "  clearance = { port = 'E.d', threshold = 0.005, pairs = 'E.p' },\n}\n");
                  }),
                  "entry.lua:3: run.clearance: `pairs` (a vector<double> port, m per pair) and `pair_names` "
                  "(\"Comp.operation\" naming them) go together");
  EXPECT_CONTAINS(messageOf([] {
                    read("run = {\n  charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n"
                         "  summary = { { name = 'f', count = { 'e_x' },\n"
                         "                expected = { { event = 'e_y', during = 'a:root.R' } } } },\n}\n");
                  }),
                  "entry.lua:4: run.summary[1].expected[1]: event 'e_y' is not one of `count`");
  EXPECT_CONTAINS(messageOf([] {
                    read("run = {\n  charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n"
                         "  summary = { { name = 'f', count = { 'e_x' },\n"
                         "                expected = { { event = 'e_x', during = 'root.R' } } } },\n}\n");
                  }),
                  "state 'root.R' must be written chart:state path");
}

TEST(RunSpec, JointVelocityLimitsAreAPropertyOrTheLimitsThemselves) {
  const RunSpec spec = read("run = {\n  charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n"
                            "  tracking = { { name = 't', commanded = 'C.c', measured = 'C.m', joints = 'C.q',\n"
                            "                 max_velocity = { 3.14, 0.1 } } },\n}\n");
  EXPECT_EQ(spec.tracking[0].max_velocity_values, (std::vector<double>{3.14, 0.1}));
  EXPECT_TRUE(spec.tracking[0].max_velocity.empty());
  EXPECT_CONTAINS(messageOf([] {
                    read("run = {\n  charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n"
                         "  tracking = { { name = 't', commanded = 'C.c', measured = 'C.m', joints = 'C.q',\n"
                         "                 max_velocity = { 3.14, -1 } } },\n}\n");
                  }),
                  "run.tracking[1]: `max_velocity` must be a list of positive numbers (entry 2 is not)");
}

TEST(RunSpec, AnEntryFileWithoutARunTableSaysWhatTheRunnerNeeds) {
  EXPECT_EQ(messageOf([] { read("x = 1\n"); }),
            file() + ": no `run = { charts = { ... } }` table: the runner needs to know which task charts end the run "
                     "(run/README.md)");
}

TEST(RunSpec, ATableWithoutChartsNamesItsLine) {
  EXPECT_EQ(messageOf([] { read("-- an app\nrun = {\n  title = 'x',\n}\n"); }),
            file() + ":2: run: needs `charts = { { name = , supervisor = , done = } }`: the charts that end the run");
}

TEST(RunSpec, AChartWithoutItsDoneStateNamesTheEntry) {
  EXPECT_EQ(messageOf([] { read("run = {\n  charts = {\n    { name = \"a\", supervisor = \"S\" },\n  },\n}\n"); }),
            file() + ":3: run.charts[1]: needs `done` (a string)");
}

TEST(RunSpec, BadValuesAreRefusedWithWhatIsExpected) {
  EXPECT_CONTAINS(messageOf([] {
                    read("run = {\n  charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n"
                         "  record = { period = 0, ports = {} },\n}\n");
                  }),
                  "run.record: `period` must be a finite positive number");
  EXPECT_CONTAINS(messageOf([] {
                    read("run = {\n  charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n"
                         "  summary = { { name = 'x', port = 'C.v' } },\n}\n");
                  }),
                  "run.summary[1]: give one of on_enter = \"chart:state\", on_leave = \"chart:state\" (when to sample)");
  EXPECT_CONTAINS(messageOf([] {
                    read("run = {\n  charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n"
                         "  tracking = { { name = 't', commanded = 'C.c', measured = 'C.m', joints = 'C.q' } },\n}\n");
                  }),
                  "run.tracking[1]: `joints` needs `max_velocity = \"Comp.property\"`");
  EXPECT_CONTAINS(messageOf([] {
                    read("run = {\n  charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n"
                         "  actions = { { on = { state = 'root.Wait' }, call = 'C.op' } },\n}\n");
                  }),
                  "state 'root.Wait' must be written chart:state path, e.g. needle:root.WaitCryoCycle");
  EXPECT_CONTAINS(messageOf([] {
                    read("run = {\n  charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n"
                         "  actions = { { on = { time = 1 }, call = 'op' } },\n}\n");
                  }),
                  "'op' must be written Component.operation");
}

// A figure of paths (each its own x and y columns) with labelled marks where a chart entered a
// state: Fig. 6.7 of the thesis from a run.
TEST(RunSpec, PlotsOfPathsWithLabelledMarks) {
  const RunSpec spec = read(R"(run = {
  charts = { { name = "arm", supervisor = "S", done = "root.Done" } },
  plots = { { title = "path", unit = "m", x_unit = "m", from = "arm:root.B",
              paths = { { label = "nominal", x = "G.pose.y", y = "G.pose.z", dashed = true },
                        { label = "actual", x = "K.pose.y", y = "K.pose.z",
                          marks = { { "A", "arm:root.A" }, { "B", "arm:root.B.Moving" } } } } } },
}
)");
  ASSERT_EQ(spec.plots.size(), 1u);
  const PlotSpec& p = spec.plots[0];
  EXPECT_TRUE(p.series.empty());
  EXPECT_EQ(p.from_chart, "arm");
  EXPECT_EQ(p.from_state, "root.B");
  ASSERT_EQ(p.paths.size(), 2u);
  EXPECT_EQ(p.paths[0].label, "nominal");
  EXPECT_EQ(p.paths[0].x, "G.pose.y");
  EXPECT_EQ(p.paths[0].y, "G.pose.z");
  EXPECT_TRUE(p.paths[0].dashed);
  EXPECT_TRUE(p.paths[0].marks.empty());
  EXPECT_FALSE(p.paths[1].dashed);
  ASSERT_EQ(p.paths[1].marks.size(), 2u);
  EXPECT_EQ(p.paths[1].marks[1].label, "B");
  EXPECT_EQ(p.paths[1].marks[1].chart, "arm");
  EXPECT_EQ(p.paths[1].marks[1].state, "root.B.Moving");
}

TEST(RunSpec, BadPathPlotsAreRefusedWithWhatIsExpected) {
  const auto plot = [](const std::string& entry) {
    return messageOf([&] {
      read("run = {\n  charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n  plots = { " + entry + " },\n}\n");
    });
  };
  EXPECT_CONTAINS(plot("{ title = 'p' }"),
                  ":3: run.plots[1]: needs either `series = { \"Comp.port\", ... }` or `paths = { { label = , x = , y = "
                  "}, ... }`");
  EXPECT_CONTAINS(plot("{ title = 'p', series = { 'C.v' }, paths = { { label = 'l', x = 'C.x', y = 'C.y' } } }"),
                  "needs either `series");
  EXPECT_CONTAINS(plot("{ title = 'p', x = 'C.t', paths = { { label = 'l', x = 'C.x', y = 'C.y' } } }"),
                  "run.plots[1]: `x` is for series; each path names its own x and y columns");
  EXPECT_CONTAINS(plot("{ title = 'p', from = 'a:root.B', series = { 'C.v' } }"), "run.plots[1]: `from` is for paths");
  EXPECT_CONTAINS(plot("{ title = 'p', paths = { { label = 'l', x = 'C.x' } } }"),
                  "run.plots[1].paths[1]: needs `y` (a string)");
  EXPECT_CONTAINS(plot("{ title = 'p', paths = { { label = 'l', x = 'C.x', y = 'C.y', marks = { 'A' } } } }"),
                  "run.plots[1].paths[1]: `marks` entry 1 is not a pair of strings; write marks = { { \"A\", "
                  "\"chart:state path\" }, ... }");
  EXPECT_CONTAINS(plot("{ title = 'p', paths = { { label = 'l', x = 'C.x', y = 'C.y', marks = { { 'A', 'root.A' } } } } }"),
                  "state 'root.A' must be written chart:state path");
}

}  // namespace
}  // namespace cobra::run

namespace cobra::run {
namespace {

TEST(RunSpec, ReadsTheStudioTableInTheOrderOfItsLines) {
  const RunSpec spec = read(R"(
run = {
  charts = { { name = "a", supervisor = "ASup", done = "root.Done" } },
  studio = {
    scene = "Planner",
    robots = { zeta = "Z.q",
               alpha = { "A.q", joints = 6 },
               puma = { "P.q", kinematics = "Kin" } },
    extras = { ball = { sphere = "B.pose", radius = "B.r" },
               image = { plane = "U.pose", size = { 0.06, 0.1 } } },
    signals = { "C.out", "D.pose.z" },
    inputs = { mounted = { "Surgeon.say", "e_needle_mounted" },
               recover = { "Surgeon.say", "e_recover", label = "Recover now", event = "e_recover_now" } },
  },
}
)");
  const StudioSpec& s = spec.studio;
  ASSERT_TRUE(s.declared);
  EXPECT_EQ(s.scene, "Planner");
  ASSERT_EQ(s.robots.size(), 3u);
  EXPECT_EQ(s.robots[0].name, "zeta");  // the order of the lines, not of Lua's table
  EXPECT_EQ(s.robots[0].where.line, 6);
  EXPECT_EQ(s.robots[1].joints, "A.q");
  EXPECT_EQ(s.robots[1].count, 6);
  EXPECT_EQ(s.robots[1].kinematics, "");
  EXPECT_EQ(s.robots[2].joints, "P.q");
  EXPECT_EQ(s.robots[2].kinematics, "Kin");  // drawn from that solver's chain
  EXPECT_EQ(s.robots[2].where.line, 8);
  ASSERT_EQ(s.extras.size(), 2u);
  EXPECT_EQ(s.extras[0].kind, "sphere");
  EXPECT_EQ(s.extras[0].radius, "B.r");
  EXPECT_EQ(s.extras[1].kind, "plane");
  EXPECT_DOUBLE_EQ(s.extras[1].height, 0.1);
  ASSERT_EQ(s.signals.size(), 2u);
  EXPECT_EQ(s.signals[1].first, "D.pose.z");
  ASSERT_EQ(s.inputs.size(), 2u);
  EXPECT_EQ(s.inputs[0].label, "Mounted");
  EXPECT_EQ(s.inputs[0].call, "Surgeon.say");
  EXPECT_EQ(s.inputs[0].args, std::vector<std::string>{"e_needle_mounted"});
  EXPECT_EQ(s.inputs[0].event, "e_needle_mounted");  // default: the first argument
  EXPECT_EQ(s.inputs[1].label, "Recover now");
  EXPECT_EQ(s.inputs[1].event, "e_recover_now");
  EXPECT_EQ(s.inputs[1].where.line, 13);
  EXPECT_FALSE(read("run = { charts = { { name = 'a', supervisor = 'S', done = 'd' } } }").studio.declared);
}

TEST(RunSpec, ABadStudioEntryIsOneLineWithFileLineAndWhatIsExpected) {
  const std::string head = "run = { charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n";
  EXPECT_EQ(messageOf([&] { read(head + "studio = { extras = { ball = { sphere = 'B.pose' } } } }"); }),
            file() + ":2: run.studio.extras.ball: needs `radius` (a string)");
  EXPECT_EQ(messageOf([&] { read(head + "studio = { extras = {\n image = { plane = 'U.pose' } } } }"); }),
            file() + ":3: run.studio.extras.image: a plane needs `size = { width, height }` in m");
  EXPECT_EQ(messageOf([&] { read(head + "studio = { inputs = {\n go = 'Surgeon.say' } } }"); }),
            file() + ":3: run.studio.inputs.go: must be { \"Comp.operation\", args..., label = \"...\" }, e.g. "
                     "{ \"Surgeon.say\", \"e_needle_mounted\" }");
  EXPECT_EQ(messageOf([&] { read(head + "studio = { robots = { isur = 'ISURq' } } }"); }),
            file() + ":2: run.studio.robots.isur: 'ISURq' must be written Component.port");
}

TEST(RunSpec, ReadsTheStudioExtrasOfFixedShapesAndLines) {
  const RunSpec spec = read(R"(
run = {
  charts = { { name = "a", supervisor = "ASup", done = "root.Done" } },
  studio = {
    extras = { tumour = { spheres = "Patient.tumour" },
               forbidden = { capsules = "Monitor.forbidden_regions" },
               surface = { cylinders = "World.surface_cylinder" },
               layers = { slabs = "Patient.layer_depths", pose = "Patient.phantom_pose", size = "phantom" },
               sheet = { slabs = "P.depths", pose = "P.pose", size = { 0.3, 0.2 } },
               edges = { polyline = "Patient.woundEdges", strands = 2, max = 100 },
               stitches = { segments = "Patient.stitchLines" } },
  },
}
)");
  const std::vector<StudioSpec::Extra>& e = spec.studio.extras;
  ASSERT_EQ(e.size(), 7u);
  EXPECT_EQ(e[0].kind, "spheres");
  EXPECT_EQ(e[0].pose, "Patient.tumour");
  EXPECT_EQ(e[1].kind, "capsules");
  EXPECT_EQ(e[2].kind, "cylinders");
  EXPECT_EQ(e[3].kind, "slabs");
  EXPECT_EQ(e[3].frame, "Patient.phantom_pose");
  EXPECT_EQ(e[3].footprint, "phantom");
  EXPECT_EQ(e[3].where.line, 8);
  EXPECT_EQ(e[4].footprint, "");
  EXPECT_DOUBLE_EQ(e[4].width, 0.3);
  EXPECT_DOUBLE_EQ(e[4].height, 0.2);
  EXPECT_EQ(e[5].kind, "polyline");
  EXPECT_EQ(e[5].strands, 2);
  EXPECT_EQ(e[5].max, 100);
  EXPECT_EQ(e[6].kind, "segments");
  EXPECT_EQ(e[6].strands, 1);
}

TEST(RunSpec, ABadStudioExtraOfTheNewKindsIsOneLineWithFileLine) {
  const std::string head = "run = { charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n";
  EXPECT_EQ(messageOf([&] { read(head + "studio = { extras = {\n layers = { slabs = 'P.depths', size = { 1, 1 } } } } }"); }),
            file() + ":3: run.studio.extras.layers: needs `pose` (a string)");
  EXPECT_EQ(messageOf([&] { read(head + "studio = { extras = {\n layers = { slabs = 'P.depths', pose = 'P.pose' } } } }"); }),
            file() + ":3: run.studio.extras.layers: slabs need `size = { width, height }` in m or `size = \"object\"` (a box of "
                     "run.studio.scene)");
  EXPECT_EQ(messageOf([&] { read(head + "studio = { extras = {\n layers = { slabs = 'P.depths', pose = 'Ppose', size = 'box' } } } }"); }),
            file() + ":3: run.studio.extras.layers: 'Ppose' must be written Component.property");
  EXPECT_EQ(messageOf([&] { read(head + "studio = { extras = {\n r = { capsules = 'M.regions', spheres = 'M.s' } } } }"); }),
            file() + ":3: run.studio.extras.r: give one kind, not both spheres and capsules");
  EXPECT_EQ(messageOf([&] { read(head + "studio = { extras = {\n edges = { polyline = 'P.edges', strands = 1.5 } } } }"); }),
            file() + ":3: run.studio.extras.edges: `strands` must be a whole number of lines from 1 to 1000, got 1.5");
  EXPECT_EQ(messageOf([&] { read(head + "studio = { extras = {\n t = { tumour = 'P.tumour' } } } }"); }),
            file() + ":3: run.studio.extras.t: needs one of sphere = \"Comp.framePort\" (the centre, with radius = \"Comp.port\"), "
                     "plane = \"Comp.framePort\", points, polyline or segments = \"Comp.port\" (x y z triples), spheres, capsules or "
                     "cylinders = \"Comp.property\", slabs = \"Comp.property\" (depth pairs, with pose and size)");
}

// A count beyond its range (finite and positive, but no int: 1e20) is refused, not converted.
TEST(RunSpec, AStudioCountBeyondItsRangeIsOneLineWithFileLineTheEntryAndTheRange) {
  const std::string head = "run = { charts = { { name = 'a', supervisor = 'S', done = 'd' } },\n";
  EXPECT_EQ(messageOf([&] { read(head + "studio = { extras = {\n cloud = { points = 'P.cloud', max = 1e20 } } } }"); }),
            file() + ":3: run.studio.extras.cloud: `max` must be a whole number of points from 1 to 100000, got 1e+20");
  EXPECT_EQ(messageOf([&] { read(head + "studio = { extras = {\n edges = { polyline = 'P.edges', strands = 4294967297 } } } }"); }),
            file() + ":3: run.studio.extras.edges: `strands` must be a whole number of lines from 1 to 1000, got 4294967297");
  EXPECT_EQ(messageOf([&] { read(head + "studio = { robots = {\n arm = { 'A.q', joints = 1e10 } } } }"); }),
            file() + ":3: run.studio.robots.arm: `joints` must be a whole number of joints from 1 to 64, got 10000000000");
  const RunSpec spec = read(head + "studio = { extras = { cloud = { points = 'P.cloud', max = 100000 } } } }");
  EXPECT_EQ(spec.studio.extras.at(0).max, 100000);
}

// Every section other than the runner's own names a registered observer (observer.hpp); the
// sections cobra registers itself are known without any package loaded.
TEST(RunSpec, ASectionNoObserverIsRegisteredForIsOneLineWithFileLineAndTheKnownSections) {
  const std::string path = file();
  EXPECT_EQ(messageOf([&] {
              read("run = {\n  charts = { { name = \"a\", supervisor = \"S\", done = \"root.D\" } },\n"
                   "  trackin = { },\n}\n");
            }),
            path + ":3: run.trackin: unknown section 'trackin' (no observer of this name is registered: a package "
                   "adds one with ObserverRegistry::add); did you mean 'tracking'? known sections: title, charts, fold, "
                   "failures, explain, safe_stop_reason, safe_stop_linger, stall_notice, step, actions, record, plots, summary, "
                   "tracking, clearance, studio");
}

TEST(RunSpec, EachSectionIsMadeIntoItsObserverInTheRegistrysOrder) {
  const RunSpec spec = read(R"(
run = {
  charts = { { name = "a", supervisor = "S", done = "root.D" } },
  clearance = { port = "E.d", threshold = 0.005 },
  summary = { { name = "N", count = { "e_x" } } },
  record = { ports = { "C.out" } },
}
)");
  ASSERT_EQ(spec.observers.size(), 3u);
  EXPECT_EQ(spec.observers[0].name, "record");
  EXPECT_EQ(spec.observers[1].name, "summary");
  EXPECT_EQ(spec.observers[2].name, "clearance");
  EXPECT_EQ(spec.observers[2].where.line, 4);
  EXPECT_NE(spec.observers[2].observer, nullptr);
}

}  // namespace
}  // namespace cobra::run
