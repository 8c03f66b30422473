// CSV codecs (csv_codec.hpp): a record reported by its fields (columns <port>.<field>[.<sub>] with
// each field's unit), recorded without allocating, and a type without a registered codec as text.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <kdl/frames.hpp>

#include "cobra/components/reporting/csv_codec.hpp"
#include "cobra/components/reporting/reporter.hpp"
#include "cobra/core/core.hpp"
#include "cobra/core/record.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "test_files.hpp"

namespace {
struct Gains {
  double stiffness = 0.0;
  int samples = 0;
};
struct Reading {
  double depth = 0.0;
  bool touching = false;
  KDL::Frame pose;
  Gains gains;
  std::string label;
};
struct Unregistered {
  double a = 0.0;
};
}  // namespace

template <>
struct cobra::core::DataTypeTraits<Gains> : cobra::core::RecordTraits<Gains> {
  static constexpr std::string_view name = "csv_test.Gains";
  static constexpr auto fields = std::tuple{field("stiffness", &Gains::stiffness, "N/m"), field("samples", &Gains::samples, "1")};
};
template <>
struct cobra::core::DataTypeTraits<Reading> : cobra::core::RecordTraits<Reading> {
  static constexpr std::string_view name = "csv_test.Reading";
  static constexpr auto fields =
      std::tuple{field("depth", &Reading::depth, "m", "image depth"), field("touching", &Reading::touching),
                 field("pose", &Reading::pose), field("gains", &Reading::gains), field("label", &Reading::label)};
};
template <>
struct cobra::core::DataTypeTraits<Unregistered> : cobra::core::RecordTraits<Unregistered> {
  static constexpr std::string_view name = "csv_test.Unregistered";
  static constexpr auto fields = std::tuple{field("a", &Unregistered::a, "s")};
};

namespace cobra::components {
namespace {

using namespace std::chrono_literals;
using test::readLines;
using test::ScratchDir;

class Writer : public core::Component {
 public:
  explicit Writer(std::string name) : Component(std::move(name), core::Role::Bridge, "writes a record") {
    addPort(out);
    addPort(other);
    value.label.reserve(64);
    value.label = "liver";
  }
  void updateHook() override {
    value.depth += 0.5;
    value.gains.samples += 1;
    value.touching = !value.touching;
    out.write(value);
  }
  Reading value;
  core::OutputPort<Reading> out{"reading", "the probe's reading", "m"};
  core::OutputPort<Unregistered> other{"other", "", ""};
};

TEST(CsvCodec, ARecordHasOneColumnPerScalarOfItsFieldsWithTheFieldsUnits) {
  std::vector<CsvColumn> columns;
  CsvCodec<Reading>::columns("m", 0, columns);
  std::vector<std::string> names;
  for (const CsvColumn& c : columns) names.push_back(c.suffix + " [" + c.unit + "]" + (c.numeric ? "" : " text"));
  EXPECT_EQ(names, (std::vector<std::string>{".depth [m]", ".touching []", ".pose.x [m]", ".pose.y [m]", ".pose.z [m]",
                                             ".pose.qx [1]", ".pose.qy [1]", ".pose.qz [1]", ".pose.qw [1]",
                                             ".gains.stiffness [N/m]", ".gains.samples [1]", ".label [] text"}));
}

TEST(CsvCodec, TheReporterRecordsARegisteredRecordByItsFieldsAndAnUnregisteredTypeAsText) {
  registerCsvType<Reading>();
  ASSERT_NE(findCsvType(core::typeInfo<Reading>()), nullptr);
  EXPECT_EQ(findCsvType(core::typeInfo<Unregistered>()), nullptr);
  ScratchDir dir;
  core::LockstepClock clock;
  Writer writer("W");
  writer.value.pose = KDL::Frame(KDL::Vector(0.1, 0.2, 0.3));
  writer.value.gains.stiffness = 250.0;
  Reporter reporter("Rep");
  reporter.reportPort(writer.out);
  reporter.reportPort(writer.other);
  reporter.setProperty("file_path", dir.file("record.csv"));
  clock.add(writer, 1ms);
  clock.add(reporter, 1ms);
  ASSERT_TRUE(writer.configure() && writer.start());
  ASSERT_TRUE(reporter.configure() && reporter.start());
  writer.other.write(Unregistered{2.5});
  clock.advance(2ms);
  ASSERT_TRUE(reporter.stop());
  const auto lines = readLines(dir.file("record.csv"));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0],
            "time [s],W.reading.depth [m],W.reading.touching,W.reading.pose.x [m],W.reading.pose.y [m],"
            "W.reading.pose.z [m],W.reading.pose.qx [1],W.reading.pose.qy [1],W.reading.pose.qz [1],"
            "W.reading.pose.qw [1],W.reading.gains.stiffness [N/m],W.reading.gains.samples [1],W.reading.label,"
            "W.other");
  EXPECT_EQ(lines[1], "0,0.5,1,0.1,0.2,0.3,0,0,0,1,250,1,liver,{a = 2.5}");
  EXPECT_EQ(lines[2], "0.001,1,0,0.1,0.2,0.3,0,0,0,1,250,2,liver,{a = 2.5}");
}

TEST(CsvCodec, RecordingARecordAllocatesNothing) {
  registerCsvType<Reading>();
  ScratchDir dir;
  core::LockstepClock clock;
  Writer writer("W");
  Reporter reporter("Rep");
  reporter.reportPort(writer.out);
  reporter.setProperty("file_path", dir.file("alloc.csv"));
  reporter.setProperty("queue_rows", 10000);
  clock.add(writer, 1ms);
  clock.add(reporter, 1ms);
  ASSERT_TRUE(writer.configure() && writer.start());
  ASSERT_TRUE(reporter.configure() && reporter.start());
  clock.advance(10ms);  // warm-up
  EXPECT_EQ(test_support::allocationsDuring([&] { clock.advance(1000ms); }), 0)
      << "allocations in 1000 steps of a record's writer and the reporter";
  ASSERT_TRUE(reporter.stop());
  EXPECT_EQ(readLines(dir.file("alloc.csv")).size(), 1u + 1010u);
}

TEST(CsvCodec, TheNumericViewGivesOneNumberPerColumnForAPlot) {
  registerCsvType<Reading>();
  core::OutputPort<Reading> out("reading", "", "m");
  const CsvType* entry = findCsvType(core::typeInfo<Reading>());
  auto source = entry->make_source(out, out.makeReader("plot", ""), 0);
  core::connectPorts(out, source->reader());
  Reading r;
  r.depth = 0.25;
  r.gains = {3.0, 4};
  r.label = "text";
  out.write(r);
  ASSERT_EQ(source->sample(), core::FlowStatus::NewData);
  std::vector<double> values(source->headers().size());
  RowWriter row(values.data(), values.size());
  EXPECT_EQ(test_support::allocationsDuring([&] { source->format(row); }), 0);
  ASSERT_EQ(row.size(), 12u);
  EXPECT_EQ(values[0], 0.25);
  EXPECT_EQ(values[8], 1.0);  // pose.qw
  EXPECT_EQ(values[9], 3.0);
  EXPECT_EQ(values[10], 4.0);
  EXPECT_TRUE(std::isnan(values[11]));  // the label: text
}

// Made with 0 elements, a vector<double> source writes each value in as many cells as it has:
// for a reader that names the columns from the first value (run::NumericTap).
TEST(CsvCodec, AVariableLengthSourceOfZeroElementsWritesTheValuesLength) {
  core::OutputPort<std::vector<double>> out("values", "", "m");
  const CsvType* entry = findCsvType(core::typeInfo<std::vector<double>>());
  auto source = entry->make_source(out, out.makeReader("plot", ""), 0);
  core::connectPorts(out, source->reader());
  EXPECT_TRUE(source->headers().empty());
  EXPECT_EQ(source->length(), 0u) << "no value read yet";
  out.write(std::vector<double>{1.0, 2.0, 3.0});
  ASSERT_EQ(source->sample(), core::FlowStatus::NewData);
  EXPECT_EQ(source->length(), 3u);
  std::vector<double> values(4, -1.0);
  RowWriter row(values.data(), values.size());
  source->format(row);
  EXPECT_EQ(values, (std::vector<double>{1.0, 2.0, 3.0, -1.0}));
  out.write(std::vector<double>{4.0, 5.0, 6.0});
  ASSERT_EQ(source->sample(), core::FlowStatus::NewData);
  RowWriter again(values.data(), values.size());
  EXPECT_EQ(test_support::allocationsDuring([&] { source->format(again); }), 0);
  EXPECT_EQ(values[2], 6.0);
}

TEST(CsvCodec, TheRegistryListsCobrasOwnTypesFirstThenTheRegisteredOnes) {
  registerCsvType<Reading>();
  std::vector<std::string_view> names;
  for (const CsvType* entry : csvTypes()) names.push_back(entry->type_name);
  ASSERT_GE(names.size(), 14u);
  EXPECT_EQ(names[0], "double");
  EXPECT_EQ(names[12], "TaskState");
  EXPECT_NE(std::find(names.begin() + 13, names.end(), "csv_test.Reading"), names.end());
  EXPECT_EQ(std::find(names.begin(), names.end(), "csv_test.Unregistered"), names.end());
}

TEST(CsvCodec, EveryBuiltinTypeHasACsvEntry) {
  for (const char* name : {"double", "int", "bool", "string", "vector<double>", "KDL.Vector", "KDL.Rotation", "KDL.Frame",
                           "KDL.Twist", "KDL.Wrench", "KDL.JntArray", "Event", "TaskState"}) {
    const core::TypeInfo* type = core::TypeRegistry::find(name);
    ASSERT_NE(type, nullptr) << name;
    const CsvType* entry = findCsvType(*type);
    ASSERT_NE(entry, nullptr) << name;
    EXPECT_EQ(entry->needs_length, std::string_view(name) == "vector<double>" || std::string_view(name) == "KDL.JntArray");
  }
}

}  // namespace
}  // namespace cobra::components
