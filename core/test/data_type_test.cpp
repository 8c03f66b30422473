// Unit tests of the type registry (data_type.hpp): names, kinds, lookup, and the text form of
// every built-in type (print/parse round trips and refusals).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <limits>
#include <random>
#include <string>
#include <typeindex>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/core/data_type.hpp"
#include "cobra/core/error.hpp"

namespace {
struct TestColour {
  int r = 0;
};
// Two types that claim one name (a copy-pasted DataTypeTraits).
struct TwinA {
  int v = 0;
};
struct TwinB {
  int v = 0;
};
template <class T>
struct TwinTraits {
  static constexpr std::string_view name = "test.Twin";
  static constexpr cobra::core::DataKind kind = cobra::core::DataKind::Pure;
  static constexpr std::string_view format = "an integer";
  static std::string print(const T& t) { return std::to_string(t.v); }
  static bool parse(std::string_view text, T& out) { return cobra::core::DataTypeTraits<int>::parse(text, out.v); }
};
}  // namespace

template <>
struct cobra::core::DataTypeTraits<TwinA> : TwinTraits<TwinA> {};
template <>
struct cobra::core::DataTypeTraits<TwinB> : TwinTraits<TwinB> {};

// A user type registered the documented way, to check that registration reaches the registry.
template <>
struct cobra::core::DataTypeTraits<TestColour> {
  static constexpr std::string_view name = "test.Colour";
  static constexpr DataKind kind = DataKind::Pure;
  static constexpr std::string_view format = "an integer red value";
  static std::string print(const TestColour& c) { return std::to_string(c.r); }
  static bool parse(std::string_view text, TestColour& out) { return DataTypeTraits<int>::parse(text, out.r); }
};

namespace cobra::core {

// Readable gtest output for events (found by argument-dependent lookup).
void PrintTo(const Event& event, std::ostream* os) { *os << printValue(event); }

namespace {

template <class T>
bool parseText(std::string_view text, T& out) {
  return DataTypeTraits<T>::parse(text, out);
}

template <class T>
T reparsed(const T& value) {
  T back{};
  const std::string text = printValue(value);
  EXPECT_TRUE(parseText(text, back)) << "cannot parse back \"" << text << "\"";
  return back;
}

template <class T>
void expectRefused(std::string_view text) {
  T out{};
  EXPECT_FALSE(parseText(text, out)) << DataTypeTraits<T>::name << " accepted \"" << text << "\"";
}

struct Expected {
  std::string_view name;
  DataKind kind;
  std::type_index id;
};

std::vector<Expected> builtins() {
  return {{"double", DataKind::Pure, typeid(double)},
          {"int", DataKind::Pure, typeid(int)},
          {"bool", DataKind::Pure, typeid(bool)},
          {"string", DataKind::Pure, typeid(std::string)},
          {"vector<double>", DataKind::Pure, typeid(std::vector<double>)},
          {"KDL.Vector", DataKind::Pure, typeid(KDL::Vector)},
          {"KDL.Rotation", DataKind::Pure, typeid(KDL::Rotation)},
          {"KDL.Frame", DataKind::Pure, typeid(KDL::Frame)},
          {"KDL.Twist", DataKind::Pure, typeid(KDL::Twist)},
          {"KDL.Wrench", DataKind::Pure, typeid(KDL::Wrench)},
          {"KDL.JntArray", DataKind::Pure, typeid(KDL::JntArray)},
          {"Event", DataKind::Logic, typeid(Event)},
          {"TaskState", DataKind::Logic, typeid(TaskState)}};
}

// --- registry --------------------------------------------------------------------------------

// Found by fuzz/value_text_fuzz: a half turn's quaternion has qw = ±0 depending on the path, so
// printing -0 made print(parse(print(x))) differ from print(x).
TEST(DataTypeText, TaskStateIsAPathWithoutSpaces) {
  TaskState state;
  ASSERT_TRUE(DataTypeTraits<TaskState>::parse(" root.on.moving ", state));
  EXPECT_EQ(printValue(state), "root.on.moving");
  EXPECT_FALSE(DataTypeTraits<TaskState>::parse("root on", state));
  EXPECT_FALSE(DataTypeTraits<TaskState>::parse(std::string(128, 'x'), state));
}

TEST(DataTypeText, NegativeZeroPrintsAsZeroSoPrintedTextIsStable) {
  EXPECT_EQ(printValue(-0.0), "0");
  KDL::Frame frame;
  ASSERT_TRUE(DataTypeTraits<KDL::Frame>::parse("[0, 0, -0, -0, 1, 0, -0]", frame));
  const std::string printed = printValue(frame);
  EXPECT_EQ(printed, "[0, 0, 0, 0, 1, 0, 0]");
  KDL::Frame again;
  ASSERT_TRUE(DataTypeTraits<KDL::Frame>::parse(printed, again));
  EXPECT_EQ(printValue(again), printed);
}

TEST(TypeRegistry, EveryBuiltinIsRegisteredWithItsNameKindAndFormat) {
  for (const Expected& e : builtins()) {
    const TypeInfo* info = TypeRegistry::find(e.name);
    ASSERT_NE(info, nullptr) << e.name;
    EXPECT_EQ(info->name, e.name);
    EXPECT_EQ(info->kind, e.kind) << e.name;
    EXPECT_EQ(info->id, e.id) << e.name;
    EXPECT_FALSE(info->format.empty()) << e.name;
  }
}

TEST(TypeRegistry, EventAndTaskStateAreTheLogicBuiltins) {
  EXPECT_EQ(typeInfo<Event>().kind, DataKind::Logic);
  EXPECT_EQ(typeInfo<TaskState>().kind, DataKind::Logic);
  EXPECT_EQ(typeInfo<double>().kind, DataKind::Pure);
  EXPECT_EQ(typeInfo<KDL::Frame>().kind, DataKind::Pure);
  EXPECT_EQ(toString(DataKind::Pure), "pure data");
  EXPECT_EQ(toString(DataKind::Logic), "logic data");
}

TEST(TypeRegistry, TypeInfoOfATypeMatchesTheRegistryEntry) {
  const TypeInfo& info = typeInfo<KDL::Wrench>();
  const TypeInfo* found = TypeRegistry::find("KDL.Wrench");
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->name, info.name);
  EXPECT_EQ(found->id, info.id);
  EXPECT_EQ(info.format, DataTypeTraits<KDL::Wrench>::format);
}

TEST(TypeRegistry, FindReturnsNullForUnknownNames) {
  EXPECT_EQ(TypeRegistry::find(""), nullptr);
  EXPECT_EQ(TypeRegistry::find("Double"), nullptr);  // names are case-sensitive
  EXPECT_EQ(TypeRegistry::find("KDL.Vector3"), nullptr);
  EXPECT_EQ(TypeRegistry::find("float"), nullptr);
}

TEST(TypeRegistry, AllListsEveryBuiltinOnceSortedByName) {
  const auto all = TypeRegistry::all();
  std::vector<std::string_view> names;
  for (const TypeInfo* info : all) names.push_back(info->name);
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end()) << "duplicate names";
  for (const Expected& e : builtins())
    EXPECT_EQ(std::count(names.begin(), names.end(), e.name), 1) << e.name;
}

TEST(TypeRegistry, AUserTypeAppearsAfterItsFirstUse) {
  const TypeInfo& info = typeInfo<TestColour>();
  EXPECT_EQ(info.name, "test.Colour");
  const TypeInfo* found = TypeRegistry::find("test.Colour");
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->id, std::type_index(typeid(TestColour)));
  const auto all = TypeRegistry::all();
  EXPECT_TRUE(std::any_of(all.begin(), all.end(), [](const TypeInfo* i) { return i->name == "test.Colour"; }));
  EXPECT_EQ(printValue(TestColour{7}), "7");
}

TEST(TypeRegistry, ASecondTypeUnderARegisteredNameIsRefusedNamingTheNameAndBothTypes) {
  EXPECT_EQ(typeInfo<TwinA>().name, "test.Twin");
  std::string message;
  try {
    (void)typeInfo<TwinB>();
  } catch (const Error& e) {
    message = e.what();
  }
  EXPECT_EQ(message, "data type 'test.Twin' is registered twice, by C++ types (anonymous namespace)::TwinA and "
                     "(anonymous namespace)::TwinB; give one of them another DataTypeTraits<T>::name");
  EXPECT_EQ(TypeRegistry::find("test.Twin")->id, std::type_index(typeid(TwinA)));  // the first stays
  TypeRegistry::add(typeInfo<TwinA>());  // the same type again (another shared library's): no conflict
}

// --- round trips ------------------------------------------------------------------------------

TEST(DataTypeText, DoubleRoundTripsExactlyAndPrintsShortest) {
  for (double v : {0.0, 1.5, -3.25, 0.1, 1.0 / 3.0, 1e-300, 5e-324, 1.7976931348623157e308, M_PI, -2.0e22}) {
    EXPECT_EQ(reparsed(v), v) << printValue(v);
  }
  EXPECT_EQ(printValue(1.5), "1.5");
  EXPECT_EQ(printValue(0.1), "0.1");
  EXPECT_EQ(printValue(3.0), "3");
  EXPECT_EQ(reparsed(-0.0), 0.0);  // the same quantity; printed as 0 (see NegativeZeroPrintsAsZero...)
  EXPECT_EQ(reparsed(std::numeric_limits<double>::infinity()), std::numeric_limits<double>::infinity());
  EXPECT_EQ(reparsed(-std::numeric_limits<double>::infinity()), -std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isnan(reparsed(std::numeric_limits<double>::quiet_NaN())));
}

TEST(DataTypeText, RandomFiniteDoublesRoundTripExactly) {
  // 2000 random bit patterns (seed 20240601), every finite one must read back bit for bit.
  std::mt19937_64 rng(20240601);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const std::uint64_t bits = rng();
    double v = 0.0;
    std::memcpy(&v, &bits, sizeof v);
    if (!std::isfinite(v)) continue;
    ++checked;
    const double back = reparsed(v);
    std::uint64_t back_bits = 0;
    std::memcpy(&back_bits, &back, sizeof back);
    ASSERT_EQ(back_bits, bits) << printValue(v);
  }
  EXPECT_GT(checked, 1900);
}

TEST(DataTypeText, DoubleAcceptsSpacesAndALeadingPlus) {
  double v = 0.0;
  EXPECT_TRUE(parseText("  2.5 ", v));
  EXPECT_EQ(v, 2.5);
  EXPECT_TRUE(parseText("+4", v));
  EXPECT_EQ(v, 4.0);
  EXPECT_TRUE(parseText("-1e-3", v));
  EXPECT_EQ(v, -1e-3);
}

TEST(DataTypeText, IntRoundTripsIncludingLimits) {
  for (int v : {0, 1, -7, 123456, std::numeric_limits<int>::max(), std::numeric_limits<int>::min()})
    EXPECT_EQ(reparsed(v), v);
  int v = 0;
  EXPECT_TRUE(parseText(" +42 ", v));
  EXPECT_EQ(v, 42);
}

TEST(DataTypeText, BoolRoundTrips) {
  EXPECT_EQ(printValue(true), "true");
  EXPECT_EQ(printValue(false), "false");
  EXPECT_TRUE(reparsed(true));
  EXPECT_FALSE(reparsed(false));
}

TEST(DataTypeText, StringRoundTripsVerbatim) {
  for (const std::string& s : {std::string(), std::string("hello world"), std::string("  spaced  "),
                               std::string("[1, 2]"), std::string("ünïcødé")})
    EXPECT_EQ(reparsed(s), s);
}

TEST(DataTypeText, VectorOfDoubleRoundTripsAndAcceptsListForms) {
  for (const auto& v : {std::vector<double>{}, std::vector<double>{1.0}, std::vector<double>{1.0, 2.5, -3e-9, 0.1}})
    EXPECT_EQ(reparsed(v), v);
  EXPECT_EQ(printValue(std::vector<double>{1, 2.5, 3}), "[1, 2.5, 3]");
  EXPECT_EQ(printValue(std::vector<double>{}), "[]");
  for (std::string_view text : {"[1, 2, 3]", "[1 2 3]", "1,2,3", " [ 1 , 2 ,3 ] ", "1 2 3"}) {
    std::vector<double> v;
    EXPECT_TRUE(parseText(text, v)) << text;
    EXPECT_EQ(v, (std::vector<double>{1, 2, 3})) << text;
  }
}

TEST(DataTypeText, KdlVectorTwistWrenchRoundTripExactly) {
  const KDL::Vector vec(0.1, -2.5, 3e-7);
  EXPECT_EQ(reparsed(vec), vec);
  EXPECT_EQ(printValue(KDL::Vector(1, 2, 3)), "[1, 2, 3]");
  const KDL::Twist twist(KDL::Vector(0.1, 0.2, 0.3), KDL::Vector(-1, -2, -3));
  EXPECT_EQ(reparsed(twist), twist);
  EXPECT_EQ(printValue(twist), "[0.1, 0.2, 0.3, -1, -2, -3]");
  const KDL::Wrench wrench(KDL::Vector(5, 0, -9.81), KDL::Vector(0.01, 0.02, 0.03));
  EXPECT_EQ(reparsed(wrench), wrench);
  EXPECT_EQ(printValue(wrench), "[5, 0, -9.81, 0.01, 0.02, 0.03]");
}

TEST(DataTypeText, RandomRotationsAndFramesRoundTrip) {
  // 500 random orientations and positions (seed 7).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  std::uniform_real_distribution<double> pos(-2.0, 2.0);
  for (int i = 0; i < 500; ++i) {
    const KDL::Rotation r = KDL::Rotation::RPY(angle(rng), angle(rng) / 2, angle(rng));
    EXPECT_TRUE(KDL::Equal(reparsed(r), r, 1e-12)) << printValue(r);
    const KDL::Frame f(r, KDL::Vector(pos(rng), pos(rng), pos(rng)));
    const KDL::Frame back = reparsed(f);
    EXPECT_TRUE(KDL::Equal(back, f, 1e-12)) << printValue(f);
    EXPECT_EQ(back.p, f.p);  // positions are printed exactly
  }
  EXPECT_EQ(printValue(KDL::Rotation::Identity()), "[0, 0, 0, 1]");
  EXPECT_EQ(printValue(KDL::Frame(KDL::Vector(1, 2, 3))), "[1, 2, 3, 0, 0, 0, 1]");
}

TEST(DataTypeText, JntArrayRoundTripsForEverySize) {
  for (unsigned n : {0U, 1U, 6U, 7U}) {
    KDL::JntArray q(n);
    for (unsigned i = 0; i < n; ++i) q(i) = 0.25 * i - 1.0;
    const KDL::JntArray back = reparsed(q);
    EXPECT_EQ(back.rows(), n);
    EXPECT_TRUE(back == q);
  }
  KDL::JntArray q(3);
  q(0) = 0;
  q(1) = 0.5;
  q(2) = 1.2;
  EXPECT_EQ(printValue(q), "[0, 0.5, 1.2]");
}

TEST(DataTypeText, EventRoundTripsWithNameSourceAndStamp) {
  Event bare;
  bare.name = "e_done";
  EXPECT_EQ(reparsed(bare), bare);
  Event full;
  full.name = "e_plan_done";
  full.source = "Planner";
  full.stamp = std::chrono::milliseconds(1500);
  EXPECT_EQ(printValue(full), "e_plan_done from Planner at 1.5 s");
  EXPECT_EQ(reparsed(full), full);
  Event odd = full;
  odd.stamp = std::chrono::nanoseconds(123456789012345);
  EXPECT_EQ(reparsed(odd), odd);
  Event e;
  ASSERT_TRUE(parseText(" e_go ", e));
  EXPECT_EQ(e.name, "e_go");
  EXPECT_TRUE(e.source.empty());
  EXPECT_EQ(e.stamp.count(), 0);
}

// --- refusals ---------------------------------------------------------------------------------

TEST(DataTypeText, GarbageIsRefusedByEveryNumericType) {
  for (std::string_view text : {"", "   ", "abc", "1.5x", "1,5", "1 2", "--1", "+-1", "++1", "0x10", "1e400"})
    expectRefused<double>(text);
  for (std::string_view text : {"", "1.5", "abc", "3 4", "+-3", "--3", "99999999999", "1e3"}) expectRefused<int>(text);
  for (std::string_view text : {"", "yes", "1", "TRUE", "true false"}) expectRefused<bool>(text);
}

TEST(DataTypeText, MalformedListsAreRefused) {
  for (std::string_view text : {"[1, x]", "[1, 2", "1, 2]", "[1,,2]", "[[1]]", "[1; 2]"})
    expectRefused<std::vector<double>>(text);
  expectRefused<KDL::JntArray>("[a, b]");
  expectRefused<KDL::JntArray>("[0, 1");
}

TEST(DataTypeText, FixedSizeKdlTypesRefuseTheWrongCount) {
  for (std::string_view text : {"[1, 2]", "[1, 2, 3, 4]", "[]", ""}) expectRefused<KDL::Vector>(text);
  for (std::string_view text : {"[0, 0, 1]", "[0, 0, 0, 1, 0]"}) expectRefused<KDL::Rotation>(text);
  for (std::string_view text : {"[1, 2, 3, 0, 0, 1]", "[1, 2, 3, 0, 0, 0, 1, 0]"}) expectRefused<KDL::Frame>(text);
  for (std::string_view text : {"[1, 2, 3, 4, 5]", "[1, 2, 3, 4, 5, 6, 7]"}) {
    expectRefused<KDL::Twist>(text);
    expectRefused<KDL::Wrench>(text);
  }
}

TEST(DataTypeText, NonUnitQuaternionsAreRefused) {
  for (std::string_view text : {"[0, 0, 0, 2]", "[0, 0, 0, 0]", "[1, 1, 0, 0]", "[0, 0, 0, 0.999]"})
    expectRefused<KDL::Rotation>(text);
  expectRefused<KDL::Frame>("[0, 0, 0, 0, 0, 0, 2]");
  KDL::Rotation r;
  EXPECT_TRUE(parseText("[0, 0, 0.7071067811865476, 0.7071067811865476]", r));
  EXPECT_TRUE(KDL::Equal(r, KDL::Rotation::RotZ(M_PI / 2), 1e-12));
}

// Found by fuzz/value_text_fuzz: "[1, 0, 0.0005676, 0]" is unit to 1.6e-7, accepted, and made a
// rotation matrix that was not orthonormal (its printed quaternion then drifted at every parse).
TEST(DataTypeText, NearUnitQuaternionsAreNormalisedAndPrintedTextParsesBackToTheSameRotation) {
  KDL::Rotation r;
  ASSERT_TRUE(parseText("1,0,00000000000000.0005676,0", r));
  const KDL::Rotation product = r.Inverse() * r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(product(i, j), i == j ? 1.0 : 0.0, 1e-15) << i << "," << j;
  KDL::Rotation again;
  ASSERT_TRUE(parseText(printValue(r), again));
  EXPECT_TRUE(KDL::Equal(r, again, 1e-12));
}

TEST(DataTypeText, EventRefusesEmptySpacedAndOverlongNames) {
  expectRefused<Event>("");
  expectRefused<Event>("two words");
  expectRefused<Event>(std::string(64, 'e'));
  expectRefused<Event>("e_done from");            // "from" without a source
  expectRefused<Event>("e_done at 1.5");          // stamp without its unit
  expectRefused<Event>("e_done at x s");          // stamp that is not a number
  expectRefused<Event>("e_done from A at 1 s x");  // trailing words
  expectRefused<Event>("e_done at 1e300 s");       // no nanosecond count that large
  expectRefused<Event>("e_done at nan s");
  Event ok;
  EXPECT_TRUE(parseText(std::string(63, 'e'), ok));
}

}  // namespace
}  // namespace cobra::core
