// Unit tests of record types (record.hpp): a struct registered by its fields gets a text form that
// round-trips, refuses malformed text without touching the value, and travels on ports.

#include <gtest/gtest.h>

#include <random>
#include <string>

#include <kdl/frames.hpp>

#include "cobra/core/port.hpp"
#include "cobra/core/record.hpp"
#include "cobra/test_support/counting_new.hpp"

namespace {
struct Gains {
  double stiffness = 0.0;  // N/m
  int samples = 0;
};
struct ProbeReading {
  double depth = 0.0;  // m
  std::string label;
  KDL::Frame pose;
  Gains gains;
};
}  // namespace

template <>
struct cobra::core::DataTypeTraits<Gains> : cobra::core::RecordTraits<Gains> {
  static constexpr std::string_view name = "test.Gains";
  static constexpr auto fields =
      std::tuple{field("stiffness", &Gains::stiffness, "N/m"), field("samples", &Gains::samples, "1")};
};

template <>
struct cobra::core::DataTypeTraits<ProbeReading> : cobra::core::RecordTraits<ProbeReading> {
  static constexpr std::string_view name = "test.ProbeReading";
  static constexpr auto fields = std::tuple{field("depth", &ProbeReading::depth, "m", "image depth"),
                                            field("label", &ProbeReading::label), field("pose", &ProbeReading::pose),
                                            field("gains", &ProbeReading::gains)};
};

namespace cobra::core {
namespace {

ProbeReading sample() {
  ProbeReading r;
  r.depth = 0.05;
  r.label = "liver, \"segment\" 4 {a}";
  r.pose = KDL::Frame(KDL::Rotation::RPY(0.1, -0.2, 0.3), KDL::Vector(0.1, 0.2, -0.3));
  r.gains = {250.0, 7};
  return r;
}

bool same(const ProbeReading& a, const ProbeReading& b) {
  return a.depth == b.depth && a.label == b.label && KDL::Equal(a.pose, b.pose, 1e-12) &&
         a.gains.stiffness == b.gains.stiffness && a.gains.samples == b.gains.samples;
}

TEST(Record, IsRegisteredWithItsNameKindAndFields) {
  static_assert(RecordDataType<ProbeReading>);
  static_assert(!RecordDataType<double>);
  static_assert(fieldCount<ProbeReading>() == 4);
  const TypeInfo& info = typeInfo<ProbeReading>();
  EXPECT_EQ(info.name, "test.ProbeReading");
  EXPECT_EQ(info.kind, DataKind::Pure);
  EXPECT_EQ(TypeRegistry::find("test.ProbeReading"), TypeRegistry::find(info.name));
  std::vector<std::string> names, units;
  forEachField<ProbeReading>([&](const auto& f) {
    names.emplace_back(f.name);
    units.emplace_back(f.unit);
  });
  EXPECT_EQ(names, (std::vector<std::string>{"depth", "label", "pose", "gains"}));
  EXPECT_EQ(units, (std::vector<std::string>{"m", "", "", ""}));
}

TEST(Record, ItsFieldsAreListedAtRunTimeWithTheirTypes) {
  (void)typeInfo<ProbeReading>();  // registered at its first use (a port, registerType)
  const TypeInfo* info = TypeRegistry::find("test.ProbeReading");
  ASSERT_NE(info, nullptr);
  ASSERT_EQ(info->fields.size(), 4u);
  EXPECT_EQ(info->fields[0].name, "depth");
  EXPECT_EQ(info->fields[0].unit, "m");
  EXPECT_EQ(info->fields[0].doc, "image depth");
  EXPECT_EQ(info->fields[0].type->name, "double");
  EXPECT_EQ(info->fields[2].type->name, "KDL.Frame");
  ASSERT_EQ(info->fields[3].type->fields.size(), 2u);  // a nested record lists its own fields
  EXPECT_EQ(info->fields[3].type->fields[0].unit, "N/m");
  // Its field types are registered with it.
  EXPECT_NE(TypeRegistry::find("test.Gains"), nullptr);
  EXPECT_TRUE(TypeRegistry::find("double")->fields.empty());
  EXPECT_EQ(TypeRegistry::find("KDL.Frame")->cpp, "KDL::Frame");
  EXPECT_EQ(TypeRegistry::find("KDL.Frame")->header, "<kdl/frames.hpp>");
}

TEST(Record, PrintsEveryFieldByNameAndReadsItBack) {
  const std::string text = printValue(sample());
  const std::string head = R"({depth = 0.05, label = "liver, \"segment\" 4 {a}", pose = )";
  EXPECT_EQ(text.substr(0, head.size()), head);
  EXPECT_NE(text.find("gains = {stiffness = 250, samples = 7}"), std::string::npos) << text;
  ProbeReading back;
  ASSERT_TRUE(DataTypeTraits<ProbeReading>::parse(text, back)) << text;
  EXPECT_TRUE(same(back, sample()));
}

TEST(Record, FieldsMayComeInAnyOrder) {
  Gains g;
  ASSERT_TRUE(DataTypeTraits<Gains>::parse(" { samples = 3 ,stiffness=1.5 } ", g));
  EXPECT_EQ(g.samples, 3);
  EXPECT_EQ(g.stiffness, 1.5);
}

TEST(Record, MalformedTextIsRefusedAndLeavesTheValueAlone) {
  for (const char* bad : {"", "{}", "stiffness = 1, samples = 2", "{stiffness = 1}", "{stiffness = 1, samples = 2, x = 3}",
                          "{stiffness = 1, stiffness = 2}", "{stiffness = 1, samples = 2.5}", "{stiffness = x, samples = 2}",
                          "{stiffness = 1, samples = 2", "{stiffness = [1, samples = 2}", "{1x = 1, samples = 2}",
                          "{stiffness = , samples = 2}", "{stiffness = 1,, samples = 2}"}) {
    Gains g{9.0, 9};
    EXPECT_FALSE(DataTypeTraits<Gains>::parse(bad, g)) << bad;
    EXPECT_EQ(g.stiffness, 9.0) << bad;
    EXPECT_EQ(g.samples, 9) << bad;
  }
  ProbeReading r = sample();
  const std::string unterminated = "{depth = 1, label = \"open, pose = [0,0,0,0,0,0,1], gains = {stiffness = 1, samples = 2}}";
  EXPECT_FALSE(DataTypeTraits<ProbeReading>::parse(unterminated, r));
  EXPECT_TRUE(same(r, sample()));
}

// Seeded property: random records print and read back to the same value.
TEST(Record, RandomRecordsRoundTrip) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> real(-10.0, 10.0);
  std::uniform_int_distribution<int> integer(-1000, 1000);
  std::uniform_int_distribution<int> character(32, 126);
  for (int trial = 0; trial < 500; ++trial) {
    ProbeReading r;
    r.depth = real(rng);
    for (int i = integer(rng) % 12; i > 0; --i) r.label += static_cast<char>(character(rng));
    r.pose = KDL::Frame(KDL::Rotation::RPY(real(rng), real(rng), real(rng)), KDL::Vector(real(rng), real(rng), real(rng)));
    r.gains = {real(rng), integer(rng)};
    ProbeReading back;
    const std::string text = printValue(r);
    ASSERT_TRUE(DataTypeTraits<ProbeReading>::parse(text, back)) << text;
    EXPECT_EQ(back.depth, r.depth);
    EXPECT_EQ(back.label, r.label);
    EXPECT_TRUE(KDL::Equal(back.pose, r.pose, 1e-9)) << text;
    EXPECT_EQ(back.gains.samples, r.gains.samples);
  }
}

TEST(Record, TravelsOnAPortLikeAnyType) {
  OutputPort<ProbeReading> out("reading", "the probe's last reading", "m");
  InputPort<ProbeReading> in("reading", "the probe's last reading", "m");
  out.connectTo(in, ConnPolicy::data());
  EXPECT_EQ(out.type().name, "test.ProbeReading");
  out.write(sample());
  ProbeReading got;
  ASSERT_EQ(in.read(got), FlowStatus::NewData);
  EXPECT_TRUE(same(got, sample()));
}

// Real-time: a record of fixed size (no string longer than its capacity) is written and read
// without allocating, like any port type.
TEST(Record, WritingAndReadingItOnAPortAllocatesNothing) {
  OutputPort<ProbeReading> out("reading", "", "m");
  InputPort<ProbeReading> in("reading", "", "m");
  ProbeReading value = sample();
  value.label.reserve(64);
  out.setDataSample(value);
  out.connectTo(in, ConnPolicy::buffer(4));
  ProbeReading got = value;
  out.write(value);
  ASSERT_EQ(in.read(got), FlowStatus::NewData);  // warm-up: the reader's copy has the capacity
  const long allocations = test_support::allocationsDuring([&] {
    for (int i = 0; i < 1000; ++i) {
      value.depth = i;
      value.gains.samples = i;
      out.write(value);
      (void)in.read(got);
    }
  });
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(got.gains.samples, 999);
}

}  // namespace
}  // namespace cobra::core
