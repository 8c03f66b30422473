// The runner's recording (cobra/run/recording.hpp: Recording, cobra/run/port_tap.hpp: NumericTap) on a
// component with output ports of cobra's own numeric types: the columns and their units, the fields
// a plot may name, signals.csv, and the one-line refusals of a port of a text type or an input
// (port_tap_test: a package's record).

#include "../src/builtin_observers.hpp"
#include "cobra/run/recording.hpp"

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include <gtest/gtest.h>

#include <cmath>

#include "cobra/core/component.hpp"
#include "cobra/core/event.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::run {
namespace {

using test_support::messageOf;

/// Output ports of each type the recorder takes, one it does not, and an input.
class Outputs : public core::Component {
 public:
  explicit Outputs(std::string name) : Component(std::move(name), core::Role::Calculation, "test outputs") {
    addPort(force);
    addPort(pose);
    addPort(joints);
    addPort(wrench);
    addPort(mixed);
    addPort(events_out);
    addPort(in);
  }
  core::OutputPort<double> force{"force", "a force", "N"};
  core::OutputPort<KDL::Frame> pose{"pose", "a pose", "m"};
  core::OutputPort<KDL::JntArray> joints{"joints", "joint positions", "rad"};
  core::OutputPort<KDL::Wrench> wrench{"wrench", "a wrench", "N, N·m"};
  core::OutputPort<std::vector<double>> mixed{"mixed", "positions and angles", "m, rad"};
  core::OutputPort<core::Event> events_out{"happened", "events", ""};
  core::InputPort<double> in{"in", "an input", "1"};

 protected:
  void updateHook() override {}
};

TEST(Recording, ColumnsPerFieldWithUnitsAndEmptyCellsBeforeData) {
  core::ComponentRegistry registry;
  auto& c = registry.make<Outputs>("Out");
  Recording recording;
  for (const char* port : {"Out.force", "Out.pose", "Out.joints"}) recording.addPort(registry, port, "f.lua:1", "run.record");
  recording.addPort(registry, "Out.force", "f.lua:1", "run.record");  // twice: recorded once
  const std::size_t derived = recording.addDerived("tracking.tool.mm", "mm");
  recording.sample(0.01);  // nothing written yet
  c.force.write(2.5);
  c.pose.write(KDL::Frame(KDL::Vector(0.1, 0.2, 0.3)));
  KDL::JntArray q(2);
  q(0) = 0.5, q(1) = -0.5;
  c.joints.write(q);
  recording.set(derived, 1.25);
  recording.sample(0.02);
  EXPECT_EQ(recording.csv(),
            "time [s],Out.force [N],Out.pose.x [m],Out.pose.y [m],Out.pose.z [m],Out.pose.qx [1],Out.pose.qy [1],"
            "Out.pose.qz [1],Out.pose.qw [1],Out.joints[0] [rad],Out.joints[1] [rad],tracking.tool.mm [mm]\n"
            "0.010,,,,,,,,,,,\n"
            "0.020,2.5,0.1,0.2,0.3,0,0,0,1,0.5,-0.5,1.25\n");
  std::vector<double> x, y;
  ASSERT_TRUE(recording.column("Out.pose.z", x, y));
  EXPECT_EQ(x, std::vector<double>{0.02});  // the sample before data is left out
  EXPECT_EQ(y, std::vector<double>{0.3});
  ASSERT_TRUE(recording.column("Out.joints[1]", x, y));
  EXPECT_EQ(y, std::vector<double>{-0.5});
  EXPECT_FALSE(recording.column("Out.pose.w", x, y));
}

// Each column has the unit its type's CSV codec gives it (a wrench: N, then N·m); a unit with a
// comma (a port's "m, rad", which a vector<double> takes) is inside its header cell: quoted.
TEST(Recording, EachColumnHasItsCodecsUnitAndAHeaderCellWithACommaIsQuoted) {
  core::ComponentRegistry registry;
  auto& c = registry.make<Outputs>("Out");
  Recording recording;
  recording.addPort(registry, "Out.wrench", "f.lua:1", "run.record");
  recording.addPort(registry, "Out.mixed", "f.lua:1", "run.record");
  c.wrench.write(KDL::Wrench(KDL::Vector(1, 2, 3), KDL::Vector(4, 5, 6)));
  c.mixed.write(std::vector<double>{0.5, 1.5});
  recording.sample(0.01);
  EXPECT_EQ(recording.csv(),
            "time [s],Out.wrench.fx [N],Out.wrench.fy [N],Out.wrench.fz [N],"
            "Out.wrench.tx [N·m],Out.wrench.ty [N·m],Out.wrench.tz [N·m],\"Out.mixed[0] [m, rad]\",\"Out.mixed[1] [m, rad]\"\n"
            "0.010,1,2,3,4,5,6,0.5,1.5\n");
}

TEST(Recording, APortWithFieldsIsNamedByOneOfThem) {
  core::ComponentRegistry registry;
  registry.make<Outputs>("Out");
  Recording recording;
  recording.addPort(registry, "Out.pose", "f.lua:1", "run.plots");
  recording.addPort(registry, "Out.force", "f.lua:1", "run.plots");
  std::vector<std::string> fields;
  EXPECT_TRUE(recording.knows("Out.force", fields));
  EXPECT_TRUE(recording.knows("Out.pose.qw", fields));
  EXPECT_FALSE(recording.knows("Out.pose.w", fields));
  EXPECT_FALSE(recording.knows("Out.pose", fields));
  EXPECT_EQ(fields, (std::vector<std::string>{"x", "y", "z", "qx", "qy", "qz", "qw"}));
}

TEST(Recording, APortOfAnotherTypeAnInputOrAnUnknownPortIsRefusedInOneLine) {
  core::ComponentRegistry registry;
  registry.make<Outputs>("Out");
  Recording recording;
  EXPECT_EQ(messageOf([&] { recording.addPort(registry, "Out.happened", "f.lua:3", "run.record"); }),
            "f.lua:3: run.record: port Out.happened is a Event, whose CSV columns are text, not numbers; types with "
            "numeric columns: double, int, bool, vector<double>, KDL.Vector, KDL.Rotation, KDL.Frame, KDL.Twist, "
            "KDL.Wrench, KDL.JntArray");
  EXPECT_EQ(messageOf([&] { recording.addPort(registry, "Out.in", "f.lua:3", "run.record"); }),
            "f.lua:3: run.record: port Out.in is an input port; observe an output port: events, force, pose, "
            "joints, wrench, mixed, happened");
  EXPECT_CONTAINS(messageOf([&] { recording.addPort(registry, "Oot.force", "f.lua:3", "run.record"); }),
                  "f.lua:3: run.record: unknown component 'Oot'; did you mean 'Out'?");
  EXPECT_EQ(messageOf([&] { recording.addPort(registry, "force", "f.lua:3", "run.record"); }),
            "f.lua:3: run.record: 'force' must be written Component.port");
}

// A path figure (run.plots[i].paths): y against x at the same sample times, and each mark on the
// first sample at or after its chart first entered a state with that prefix; a mark whose state
// was never entered is left out.
TEST(ReportFigures, APathIsDrawnWithItsMarksWhereTheChartEnteredTheirStates) {
  core::ComponentRegistry registry;
  auto& c = registry.make<Outputs>("Out");
  Recording recording;
  recording.addPort(registry, "Out.pose", "f.lua:1", "run.plots");
  for (int i = 0; i < 10; ++i) {
    c.pose.write(KDL::Frame(KDL::Vector(0, 0.01 * i, 0.1 + 0.001 * i * i)));
    recording.sample(0.1 * (i + 1));
  }
  RunSpec spec;
  PlotSpec plot;
  plot.title = "path";
  plot.unit = plot.x_unit = "m";
  PathSpec path;
  path.label = "tool";
  path.x = "Out.pose.y";
  path.y = "Out.pose.z";
  path.marks = {{"A", "arm", "root.A"}, {"B", "arm", "root.B"}, {"Z", "arm", "root.Z"}, {"C", "other", "root.C"},
                {"D", "arm", "root.D"}};
  plot.paths = {path};
  spec.plots = {plot};
  const std::vector<StateInterval> timeline = {
      {"arm chart", "root.A.Waiting", 0.0, 0.25}, {"arm chart", "root.B.Moving", 0.25, 0.61},
      {"arm chart", "root.A.Waiting", 0.61, 1.0}, {"arm chart", "root.D", 1.04, 1.04}, {"other chart", "root.C", 0.0, 1.04}};
  const std::vector<Figure> figures = plotFigures(spec.plots, recording, timeline);
  ASSERT_EQ(figures.size(), 1u);
  ASSERT_EQ(figures[0].panels.size(), 1u);
  const Panel& panel = figures[0].panels[0];
  EXPECT_EQ(panel.x_label, "Out.pose.y [m]");
  EXPECT_EQ(panel.y_label, "Out.pose.z [m]");
  ASSERT_EQ(panel.series.size(), 1u);
  const Series& s = panel.series[0];
  EXPECT_EQ(s.x.size(), 10u);
  EXPECT_NEAR(s.y[3], 0.109, 1e-12);
  EXPECT_EQ(s.marker_labels, (std::vector<std::string>{"A", "B", "C", "D"}));
  // A at the first sample (0.1 s, i = 0); B entered at 0.25 s: the sample at 0.3 s (i = 2); C at
  // 0.1 s; D after the last sample (1.0 s): the last one.
  EXPECT_EQ(s.marker_x, (std::vector<double>{0.0, 0.02, 0.0, 0.09}));
  EXPECT_NEAR(s.marker_y[1], 0.104, 1e-12);

  // From when the arm chart entered root.B (0.25 s): the samples from 0.3 s on, B's and D's marks.
  spec.plots[0].from_chart = "arm";
  spec.plots[0].from_state = "root.B";
  const Series zoomed = plotFigures(spec.plots, recording, timeline)[0].panels[0].series[0];
  EXPECT_EQ(zoomed.x.size(), 8u);
  EXPECT_DOUBLE_EQ(zoomed.x.front(), 0.02);
  EXPECT_EQ(zoomed.marker_labels, (std::vector<std::string>{"B", "D"}));
}

}  // namespace
}  // namespace cobra::run
