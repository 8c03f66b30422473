// NumericTap (cobra/run/port_tap.hpp): a port read as a row of numbers in its type's CSV codec
// columns. A record that is not one of cobra's own types, registered here as a package registers
// its type (cobra::types::registerType<T>()), is tapped and recorded by its fields with their
// units; its text field is left out; reading allocates nothing after the first value; a port of a
// type without a CSV codec or without numeric columns is refused naming the types that are tapped.
// A Tap of a vector port read into a vector with room (the clearance per pair) allocates nothing.

#include "cobra/run/port_tap.hpp"

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/core/record.hpp"
#include "cobra/run/recording.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "cobra/types/register_type.hpp"

namespace {
/// A probe's reading: not one of cobra's types, registered by the test.
struct ProbeReading {
  double depth = 0.0;   // m
  KDL::Vector tip;      // m
  bool touching = false;
  std::string label;    // text: not a number, left out of the tap
};
/// A record never registered for CSV.
struct Unlisted {
  double a = 0.0;
};
}  // namespace

template <>
struct cobra::core::DataTypeTraits<ProbeReading> : cobra::core::RecordTraits<ProbeReading> {
  static constexpr std::string_view name = "port_tap_test.ProbeReading";
  static constexpr std::string_view cpp = "ProbeReading";
  static constexpr auto fields =
      std::tuple{field("depth", &ProbeReading::depth, "m", "insertion depth"), field("tip", &ProbeReading::tip, "m"),
                 field("touching", &ProbeReading::touching), field("label", &ProbeReading::label)};
};
template <>
struct cobra::core::DataTypeTraits<Unlisted> : cobra::core::RecordTraits<Unlisted> {
  static constexpr std::string_view name = "port_tap_test.Unlisted";
  static constexpr auto fields = std::tuple{field("a", &Unlisted::a, "s")};
};

namespace cobra::run {
namespace {

using test_support::messageOf;

class Probe : public core::Component {
 public:
  explicit Probe(std::string name) : Component(std::move(name), core::Role::Calculation, "test outputs") {
    addPort(reading);
    addPort(pose);
    addPort(values);
    addPort(joints);
    addPort(unlisted);
    addPort(label);
  }
  core::OutputPort<ProbeReading> reading{"reading", "the probe's reading", ""};
  core::OutputPort<KDL::Frame> pose{"pose", "a pose", "m"};
  core::OutputPort<std::vector<double>> values{"values", "a vector", "m"};
  core::OutputPort<KDL::JntArray> joints{"joints", "joint positions", "rad"};
  core::OutputPort<Unlisted> unlisted{"unlisted", "a record without CSV codec", ""};
  core::OutputPort<std::string> label{"label", "a text", ""};

 protected:
  void updateHook() override {}
};

std::vector<std::string> namesAndUnits(const NumericTap& tap, std::size_t n) {
  std::vector<std::string> out;
  for (const NumericTap::Column& c : tap.columns(n)) out.push_back(c.field + " " + c.name + " [" + c.unit + "]");
  return out;
}

TEST(NumericTap, ARegisteredRecordIsTappedByItsNumericFieldsWithTheirUnits) {
  types::registerType<ProbeReading>();
  core::ComponentRegistry registry;
  auto& probe = registry.make<Probe>("P");
  NumericTap tap(registry, "P.reading", "f.lua:1", "run.plots");
  EXPECT_EQ(namesAndUnits(tap, 0),
            (std::vector<std::string>{"depth P.reading.depth [m]", "tip.x P.reading.tip.x [m]",
                                      "tip.y P.reading.tip.y [m]", "tip.z P.reading.tip.z [m]",
                                      "touching P.reading.touching []"}));
  std::vector<double> row{1.0};
  tap.read(row);
  EXPECT_TRUE(row.empty()) << "no value written yet";
  probe.reading.write(ProbeReading{0.02, KDL::Vector(0.1, 0.2, 0.3), true, "liver"});
  tap.read(row);
  EXPECT_EQ(row, (std::vector<double>{0.02, 0.1, 0.2, 0.3, 1.0}));
}

TEST(NumericTap, ARegisteredRecordIsRecordedInSignalsCsvAndPlottedByItsFields) {
  types::registerType<ProbeReading>();
  core::ComponentRegistry registry;
  auto& probe = registry.make<Probe>("P");
  Recording recording;
  recording.addPort(registry, "P.reading", "f.lua:1", "run.record");
  recording.sample(0.1);
  probe.reading.write(ProbeReading{0.02, KDL::Vector(0.1, 0.2, 0.3), false, "liver"});
  recording.sample(0.2);
  EXPECT_EQ(recording.csv(),
            "time [s],P.reading.depth [m],P.reading.tip.x [m],P.reading.tip.y [m],P.reading.tip.z [m],"
            "P.reading.touching\n"
            "0.100,,,,,\n"
            "0.200,0.02,0.1,0.2,0.3,0\n");
  std::vector<std::string> fields;
  EXPECT_TRUE(recording.knows("P.reading.tip.z", fields));
  EXPECT_FALSE(recording.knows("P.reading.label", fields));  // text
  EXPECT_FALSE(recording.knows("P.reading", fields));
  EXPECT_EQ(fields, (std::vector<std::string>{"depth", "tip.x", "tip.y", "tip.z", "touching"}));
  std::vector<double> x, y;
  ASSERT_TRUE(recording.column("P.reading.tip.y", x, y));
  EXPECT_EQ(x, std::vector<double>{0.2});
  EXPECT_EQ(y, std::vector<double>{0.2});
  EXPECT_EQ(recording.unitOf("P.reading.depth"), "m");
}

// vector<double> and KDL.JntArray: as many columns as the value read has, named [0], [1], ...
TEST(NumericTap, AVariableLengthTypeHasTheColumnsOfTheValueRead) {
  core::ComponentRegistry registry;
  auto& probe = registry.make<Probe>("P");
  NumericTap values(registry, "P.values", "f.lua:1", "run.plots");
  NumericTap joints(registry, "P.joints", "f.lua:1", "run.plots");
  EXPECT_TRUE(values.columns(0).empty());
  EXPECT_EQ(namesAndUnits(joints, 2), (std::vector<std::string>{"[0] P.joints[0] [rad]", "[1] P.joints[1] [rad]"}));
  probe.values.write(std::vector<double>{1.0, 2.0, 3.0});
  KDL::JntArray q(2);
  q(0) = 0.5, q(1) = -0.5;
  probe.joints.write(q);
  std::vector<double> row;
  values.read(row);
  EXPECT_EQ(row, (std::vector<double>{1.0, 2.0, 3.0}));
  joints.read(row);
  EXPECT_EQ(row, (std::vector<double>{0.5, -0.5}));
  probe.values.write(std::vector<double>{4.0});
  values.read(row);
  EXPECT_EQ(row, std::vector<double>{4.0});
}

// The studio's bridge reads its signals at every published frame of the run: after the first
// value (of each length, for a variable-length type), reading allocates nothing.
TEST(NumericTap, ReadingAllocatesNothingAfterTheFirstValue) {
  types::registerType<ProbeReading>();
  core::ComponentRegistry registry;
  auto& probe = registry.make<Probe>("P");
  NumericTap reading(registry, "P.reading", "f.lua:1", "run.studio.signals");
  NumericTap pose(registry, "P.pose", "f.lua:1", "run.studio.signals");
  NumericTap values(registry, "P.values", "f.lua:1", "run.studio.signals");
  NumericTap joints(registry, "P.joints", "f.lua:1", "run.studio.signals");
  ProbeReading sample{0.0, KDL::Vector(0.1, 0.2, 0.3), false, ""};
  sample.label.reserve(32);
  std::vector<double> vector(6, 0.0);
  KDL::JntArray q(6);
  std::vector<double> row;
  row.reserve(64);
  auto writeAll = [&](int i) {
    sample.depth = 0.001 * i;
    sample.label = i % 2 ? "odd" : "even";
    vector[0] = q(0) = i;
    probe.reading.write(sample);
    probe.pose.write(KDL::Frame(KDL::Rotation::RotZ(0.01 * i), KDL::Vector(i, 0, 0)));
    probe.values.write(vector);
    probe.joints.write(q);
  };
  auto readAll = [&] {
    reading.read(row);
    pose.read(row);
    values.read(row);
    joints.read(row);
  };
  writeAll(0);
  readAll();  // the first values: the readers' values take their sizes
  long allocations = 0;
  for (int i = 1; i <= 100; ++i) {
    writeAll(i);
    allocations += test_support::allocationsDuring(readAll);
  }
  EXPECT_EQ(allocations, 0);
  joints.read(row);
  EXPECT_EQ(row.size(), 6u);
  EXPECT_EQ(row[0], 100.0);
}

// The clearance observer reads a planner's pairDistances (vector<double>, one value per pair)
// every step into a vector it gave room for at attach: reading allocates nothing then.
TEST(Tap, AVectorPortReadIntoAVectorWithRoomAllocatesNothing) {
  core::ComponentRegistry registry;
  auto& probe = registry.make<Probe>("P");
  Tap<std::vector<double>> pairs(registry, "P.values", "f.lua:1", "run.clearance pairs", "vector<double> (m per pair)");
  std::vector<double> written(5, 0.0), read;
  read.reserve(written.size());  // as at attach: room for one value per pair
  long allocations = 0;
  for (int i = 1; i <= 100; ++i) {
    written[static_cast<std::size_t>(i % 5)] = i;
    probe.values.write(written);
    allocations += test_support::allocationsDuring([&] { EXPECT_TRUE(pairs.read(read)); });
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(read, (std::vector<double>{100.0, 96.0, 97.0, 98.0, 99.0}));
}

TEST(NumericTap, APortWithoutNumericCsvColumnsIsRefusedNamingTheTypesThatAreTapped) {
  types::registerType<ProbeReading>();
  core::ComponentRegistry registry;
  registry.make<Probe>("P");
  const std::string unlisted = messageOf([&] { NumericTap(registry, "P.unlisted", "f.lua:4", "run.record"); });
  EXPECT_EQ(unlisted.rfind("f.lua:4: run.record: port P.unlisted is a port_tap_test.Unlisted, which has no CSV codec "
                           "(register it with cobra::types::registerType<T>()); types with numeric columns: double, ",
                           0),
            0u)
      << unlisted;
  for (const char* type : {"vector<double>", "KDL.Frame", "KDL.JntArray", "port_tap_test.ProbeReading"})
    EXPECT_CONTAINS(unlisted, type);
  EXPECT_EQ(unlisted.find("string"), std::string::npos) << "a string has no numeric column: " << unlisted;
  const std::string text = messageOf([&] { NumericTap(registry, "P.label", "f.lua:5", "run.record"); });
  EXPECT_EQ(text.rfind("f.lua:5: run.record: port P.label is a string, whose CSV columns are text, not numbers; "
                       "types with numeric columns: double, ",
                       0),
            0u)
      << text;
}

}  // namespace
}  // namespace cobra::run
