// Reporter on the lockstep clock: exact CSV content, flattening, units, and error messages.

#include "cobra/components/reporting/reporter.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <numbers>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/components/signal/gain.hpp"
#include "cobra/components/signal/sine_generator.hpp"
#include "cobra/core/core.hpp"
#include "test_files.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;
using test::readLines;
using test::ScratchDir;

std::string shortest(double value) {
  char text[32];
  const auto [end, ec] = std::to_chars(text, text + sizeof text, value);
  return std::string(text, end);
}

/// Outputs of every built-in type, written by the tests themselves.
class Source : public core::Component {
 public:
  explicit Source(std::string name) : Component(std::move(name), core::Role::Bridge, "test outputs") {
    for (core::PortBase* p : std::initializer_list<core::PortBase*>{&d, &i, &b, &q, &j, &v, &r, &f, &t, &w, &s})
      addPort(*p);
    addPort(in);
  }
  core::OutputPort<double> d{"d", "", "m"};
  core::OutputPort<int> i{"i", "", "1"};
  core::OutputPort<bool> b{"b", "", ""};
  core::OutputPort<std::vector<double>> q{"q", "", "rad"};
  core::OutputPort<KDL::JntArray> j{"j", "", "rad/s"};
  core::OutputPort<KDL::Vector> v{"v", "", "N"};
  core::OutputPort<KDL::Rotation> r{"r", "", "1"};
  core::OutputPort<KDL::Frame> f{"f", "", "m"};
  core::OutputPort<KDL::Twist> t{"t", "", "m/s, rad/s"};
  core::OutputPort<KDL::Wrench> w{"w", "", "N, N·m"};
  core::OutputPort<std::string> s{"s", "", ""};
  core::InputPort<double> in{"in", "", "1"};
};

TEST(Reporter, RecordsASineAndItsGainRowByRowOnTheLockstepClock) {
  ScratchDir dir;
  core::LockstepClock clock;
  SineGenerator sine("Sine");
  Gain gain("Gain");
  Reporter reporter("Rep");
  sine.setProperty("amplitude", 2.0);
  sine.setProperty("frequency", 10.0);
  gain.setProperty("k", 3.0);
  core::connectPorts(sine.port("out"), gain.port("in"));
  reporter.reportPort(sine.port("out"));
  reporter.reportPort(gain.port("out"));
  reporter.setProperty("file_path", dir.file("sine.csv"));
  // Writers first, Reporter last: each row holds the values written in the same instant.
  clock.add(sine, 1ms);
  clock.add(gain, 1ms);
  clock.add(reporter, 1ms);
  for (core::Component* c : std::initializer_list<core::Component*>{&sine, &gain, &reporter}) {
    ASSERT_TRUE(c->configure());
    ASSERT_TRUE(c->start());
  }
  clock.advance(5ms);
  ASSERT_TRUE(reporter.stop());

  std::vector<std::string> expected = {"time [s],Sine.out [1],Gain.out [1]"};
  const char* times[] = {"0", "0.001", "0.002", "0.003", "0.004"};
  for (int k = 0; k < 5; ++k) {
    // The same arithmetic as SineGenerator and Gain, so the doubles are identical.
    const double t = std::chrono::duration<double>(std::chrono::nanoseconds(k * 1'000'000)).count();
    const double y = 0.0 + 2.0 * std::sin(2.0 * std::numbers::pi * 10.0 * t + 0.0);
    expected.push_back(std::string(times[k]) + "," + shortest(y) + "," + shortest(3.0 * y));
  }
  EXPECT_EQ(readLines(dir.file("sine.csv")), expected);
  EXPECT_EQ(reporter.columns(), (std::vector<std::string>{"time [s]", "Sine.out [1]", "Gain.out [1]"}));
  EXPECT_EQ(reporter.getProperty<int>("rows_dropped"), 0);
  // The readers are the Reporter's own ports, so introspection shows what it records.
  EXPECT_NE(reporter.findPort("Sine:out"), nullptr);
  EXPECT_TRUE(reporter.port("Gain:out").connectedTo(gain.port("out")));
}

TEST(Reporter, FlattensVectorsAndKdlTypesIntoOneColumnPerElementWithUnits) {
  ScratchDir dir;
  core::LockstepClock clock;
  Source src("Src");
  Reporter reporter("Rep");
  reporter.reportPort(src.d);
  reporter.reportPort(src.i);
  reporter.reportPort(src.b);
  reporter.reportPort(src.q, 3);
  reporter.reportPort(src.j, 2);
  reporter.reportPort(src.v);
  reporter.reportPort(src.r);
  reporter.reportPort(src.f);
  reporter.reportPort(src.t);
  reporter.reportPort(src.w);
  reporter.reportPort(src.s);
  reporter.setProperty("file_path", dir.file("all.csv"));
  clock.add(reporter, 10ms);
  ASSERT_TRUE(reporter.configure());
  ASSERT_TRUE(reporter.start());

  src.d.write(1.5);
  src.i.write(-7);
  src.b.write(true);
  src.q.write({0.25, -0.5});  // shorter than the 3 columns: the last cell stays empty
  KDL::JntArray joints(3);    // longer than the 2 columns: cut
  joints(0) = 1.0;
  joints(1) = 2.0;
  joints(2) = 3.0;
  src.j.write(joints);
  src.v.write(KDL::Vector(1, 2, 3));
  src.r.write(KDL::Rotation::Identity());
  src.f.write(KDL::Frame(KDL::Rotation::Identity(), KDL::Vector(0.1, 0.2, 0.3)));
  src.t.write(KDL::Twist(KDL::Vector(1, 2, 3), KDL::Vector(4, 5, 6)));
  src.w.write(KDL::Wrench(KDL::Vector(-1, -2, -3), KDL::Vector(0.5, 0.25, 0.125)));
  src.s.write("a, \"quoted\" text");
  clock.advance(10ms);
  ASSERT_TRUE(reporter.stop());

  const std::vector<std::string> lines = readLines(dir.file("all.csv"));
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0],
            "time [s],Src.d [m],Src.i [1],Src.b,Src.q[0] [rad],Src.q[1] [rad],Src.q[2] [rad],"
            "Src.j[0] [rad/s],Src.j[1] [rad/s],Src.v.x [N],Src.v.y [N],Src.v.z [N],"
            "Src.r.qx [1],Src.r.qy [1],Src.r.qz [1],Src.r.qw [1],"
            "Src.f.x [m],Src.f.y [m],Src.f.z [m],Src.f.qx [1],Src.f.qy [1],Src.f.qz [1],Src.f.qw [1],"
            "Src.t.vx [m/s],Src.t.vy [m/s],Src.t.vz [m/s],Src.t.wx [rad/s],Src.t.wy [rad/s],Src.t.wz [rad/s],"
            "Src.w.fx [N],Src.w.fy [N],Src.w.fz [N],Src.w.tx [N·m],Src.w.ty [N·m],Src.w.tz [N·m],Src.s");
  EXPECT_EQ(lines[1],
            "0,1.5,-7,1,0.25,-0.5,,1,2,1,2,3,0,0,0,1,0.1,0.2,0.3,0,0,0,1,1,2,3,4,5,6,-1,-2,-3,0.5,0.25,0.125,"
            "\"a, \"\"quoted\"\" text\"");
}

TEST(Reporter, WritesARowOnlyWhenAPortHasNewDataRepeatingTheOthersLastValue) {
  ScratchDir dir;
  core::LockstepClock clock;
  Source src("Src");
  Reporter reporter("Rep");
  reporter.reportPort(src.d);
  reporter.reportPort(src.i);
  reporter.reportPort(src.events(), 0);
  reporter.setProperty("file_path", dir.file("rows.csv"));
  clock.add(reporter, 1ms);
  ASSERT_TRUE(reporter.configure());
  ASSERT_TRUE(reporter.start());
  clock.advance(1ms);  // t = 0: nothing written yet, no row
  src.d.write(0.5);
  clock.advance(1ms);  // t = 0.001: d is new; i and events are still empty
  clock.advance(1ms);  // t = 0.002: nothing new, no row
  src.i.write(4);
  src.emitEvent("e_done");
  clock.advance(1ms);  // t = 0.003: i and events new, d repeats its last value
  ASSERT_TRUE(reporter.stop());
  EXPECT_EQ(readLines(dir.file("rows.csv")),
            (std::vector<std::string>{"time [s],Src.d [m],Src.i [1],Src.events", "0.001,0.5,,", "0.003,0.5,4,e_done"}));
}

TEST(Reporter, AStopAndStartAppendsToTheSameFileAndReconfigureStartsANewOne) {
  ScratchDir dir;
  core::LockstepClock clock;
  Source src("Src");
  Reporter reporter("Rep");
  reporter.reportPort(src.d);
  reporter.setProperty("file_path", dir.file("restart.csv"));
  clock.add(reporter, 1ms);
  ASSERT_TRUE(reporter.configure());
  for (double value : {1.0, 2.0}) {
    ASSERT_TRUE(reporter.start());
    src.d.write(value);
    clock.advance(1ms);
    ASSERT_TRUE(reporter.stop());
  }
  EXPECT_EQ(readLines(dir.file("restart.csv")), (std::vector<std::string>{"time [s],Src.d [m]", "0,1", "0.001,2"}));
  ASSERT_TRUE(reporter.configure());
  EXPECT_EQ(readLines(dir.file("restart.csv")), (std::vector<std::string>{"time [s],Src.d [m]"}));
  ASSERT_TRUE(reporter.cleanup());
}

TEST(Reporter, ReportsEveryOutputOfAComponentAndByNameThroughARegistry) {
  core::ComponentRegistry registry;
  auto& sine = registry.make<SineGenerator>("Sine");
  auto& gain = registry.make<Gain>("Gain");
  Reporter reporter("Rep");
  reporter.reportComponent(sine);
  reporter.reportPort(registry, "Gain.out");
  reporter.reportComponent(gain, true);  // Gain.out is already reported: only its events are left
  EXPECT_EQ(reporter.reportedPorts(), (std::vector<std::string>{"Sine.out", "Gain.out", "Gain.events"}));
  EXPECT_EQ(reporter.columns(), (std::vector<std::string>{"time [s]", "Sine.out [1]", "Gain.out [1]", "Gain.events"}));
}

TEST(Reporter, RefusesWhatItCannotReportWithMessagesThatSayWhatIsNeeded) {
  core::ComponentRegistry registry;
  auto& sine = registry.make<SineGenerator>("Sine");
  auto& gain = registry.make<Gain>("Gain");
  Source src("Src");
  Reporter reporter("Rep");
  EXPECT_EQ(test_support::messageOf([&] { reporter.reportPort(gain.port("in")); }),
            "component 'Rep': cannot report Gain.in: it is an input port; report the output port that writes it");
  reporter.reportPort(sine.port("out"));
  EXPECT_EQ(test_support::messageOf([&] { reporter.reportPort(registry, "Sine.out"); }),
            "component 'Rep': cannot report Sine.out: it is already reported; report each port once");
  EXPECT_EQ(test_support::messageOf([&] { reporter.reportPort(src.q); }),
            "component 'Rep': cannot report Src.q: it is a vector<double>, whose length is not part of its type; "
            "give its number of elements, e.g. reportPort(port, 6)");
  EXPECT_EQ(test_support::messageOf([&] { reporter.reportPort(src.d, 3); }),
            "component 'Rep': cannot report Src.d: it is a double, whose columns are fixed by its type; give no "
            "number of elements (3 was given; a number is for a type whose length is not part of it, such as "
            "vector<double> or KDL.JntArray)");
  EXPECT_EQ(test_support::messageOf([&] { reporter.reportPort(registry, "Sine"); }),
            "component 'Rep': cannot report \"Sine\": name the port as Component.port, e.g. Sine.out");
  EXPECT_EQ(test_support::messageOf([&] { reporter.reportPort(registry, "Sine.nope"); }),
            "component 'Sine' has no port 'nope'; its ports are: events, out");
  EXPECT_EQ(test_support::messageOf([&] { reporter.reportComponent(src); }),
            "component 'Rep': cannot report component 'Src': the length of q (vector<double>), j (KDL.JntArray) is "
            "not part of its type; report it first with reportPort(port, number of elements)");
  EXPECT_EQ(test_support::messageOf([&] { reporter.reportComponent(sine); }),
            "component 'Rep': cannot report component 'Sine': it has no output port left to report (its events "
            "port is reported only with include_events = true)");
  EXPECT_EQ(reporter.reportedPorts(), (std::vector<std::string>{"Sine.out"}));  // nothing half-done

  ScratchDir dir;
  reporter.setProperty("file_path", dir.file("r.csv"));
  core::LockstepClock clock;
  clock.add(reporter, 1ms);
  ASSERT_TRUE(reporter.configure());
  ASSERT_TRUE(reporter.start());
  EXPECT_EQ(test_support::messageOf([&] { reporter.reportPort(gain.port("out")); }),
            "component 'Rep': cannot report Gain.out: the reporter is Running; report ports before configure (stop "
            "and clean it up first)");
  EXPECT_EQ(test_support::messageOf([&] { reporter.setProperty("rows_dropped", 3); }),
            "component 'Rep': property 'rows_dropped' is read-only; it reports a value and cannot be set");
  ASSERT_TRUE(reporter.stop());
}

TEST(Reporter, AFileThatCannotBeOpenedFailsConfigureWithThePathAndTheReason) {
  Source src("Src");
  Reporter reporter("Rep");
  reporter.reportPort(src.d);
  reporter.setProperty("file_path", "/nonexistent-cobra-dir/r.csv");
  const core::Result result = reporter.configure();
  EXPECT_FALSE(result);
  EXPECT_EQ(result.message,
            "component 'Rep': configureHook threw: cannot open file_path '/nonexistent-cobra-dir/r.csv' for writing: "
            "No such file or directory; set file_path to a file in an existing, writable directory");
  EXPECT_EQ(reporter.state(), core::State::Exception);
  ASSERT_TRUE(reporter.recover());
  ScratchDir dir;
  reporter.setProperty("file_path", dir.file("r.csv"));
  EXPECT_TRUE(reporter.configure());
}

TEST(Reporter, ConfigureWithoutPortsSaysToReportSomeFirst) {
  Reporter reporter("Rep");
  const core::Result result = reporter.configure();
  EXPECT_EQ(result.message,
            "component 'Rep': configureHook threw: no ports to report; call reportPort or reportComponent before "
            "configure");
}

TEST(Reporter, ATinyQueueDropsRowsAndCountsEveryOneOfThem) {
  ScratchDir dir;
  core::LockstepClock clock;
  SineGenerator sine("Sine");
  Reporter reporter("Rep");
  reporter.reportPort(sine.port("out"));
  reporter.setProperty("file_path", dir.file("tiny.csv"));
  reporter.setProperty("queue_rows", 1);
  clock.add(sine, 1ms);
  clock.add(reporter, 1ms);
  ASSERT_TRUE(sine.configure() && sine.start());
  ASSERT_TRUE(reporter.configure() && reporter.start());
  // 20000 rows in a burst of simulated time: far faster than a writer thread woken per row.
  constexpr int kRows = 20000;
  clock.advance(std::chrono::milliseconds(kRows));
  ASSERT_TRUE(reporter.stop());
  const int dropped = reporter.getProperty<int>("rows_dropped");
  const auto written = static_cast<int>(readLines(dir.file("tiny.csv")).size()) - 1;
  EXPECT_GT(dropped, 0);
  EXPECT_EQ(written + dropped, kRows);
}

}  // namespace
}  // namespace cobra::components
