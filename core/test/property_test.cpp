// Unit tests of properties (property.hpp and Component's by-name access): typed and by-name get
// and set, range, read-only and type errors with their messages, and changes to a running
// component applied between two updates.

#include <gtest/gtest.h>

#include "cobra/test_support/test_support.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/core/activity.hpp"
#include "cobra/core/component.hpp"

namespace cobra::core {
namespace {

using cobra::test_support::messageOf;
using cobra::test_support::waitUntil;

using namespace std::chrono_literals;

class Gain : public Component {
 public:
  explicit Gain(std::string name = "Gain") : Component(std::move(name), Role::Calculation, "y = k u") {
    addProperty(k.range(-10.0, 10.0));
    addProperty(steps.range(1, 100));
    addProperty(label);
    addProperty(status.readOnly());
    addProperty(enabled);
    addProperty(offset);
    addProperty(tool);
  }
  Property<double> k{"k", 2.0, "1", "gain factor"};
  Property<int> steps{"steps", 5, "1", "number of steps"};
  Property<std::string> label{"label", "gain", "", "display name"};
  Property<double> status{"status", 0.0, "1", "measured value (read-only)"};
  Property<bool> enabled{"enabled", true, "", "output enabled"};
  Property<std::vector<double>> offset{"offset", {0.0, 0.0}, "m", "offset vector"};
  Property<KDL::Frame> tool{"tool", KDL::Frame::Identity(), "m", "tool frame"};
};

// --- typed and by-name access -----------------------------------------------------------------

TEST(Property, DescribesItself) {
  Gain g;
  EXPECT_EQ(g.k.name(), "k");
  EXPECT_EQ(g.k.unit(), "1");
  EXPECT_EQ(g.k.doc(), "gain factor");
  EXPECT_EQ(g.k.type().name, "double");
  EXPECT_EQ(g.k.owner(), &g);
  EXPECT_EQ(g.k.rangeText(), "[-10, 10]");
  EXPECT_EQ(g.label.rangeText(), "");
  EXPECT_TRUE(g.status.isReadOnly());
  EXPECT_FALSE(g.k.isReadOnly());
  EXPECT_EQ(g.k.where(), "component 'Gain': property 'k'");
  Property<double> loose{"loose", 1.0, "m", "no owner"};
  EXPECT_EQ(loose.where(), "property 'loose'");
}

TEST(Property, TypedGetAndSet) {
  Gain g;
  EXPECT_EQ(g.k.get(), 2.0);
  EXPECT_EQ(g.k(), 2.0);
  g.k.set(3.5);
  EXPECT_EQ(g.k.get(), 3.5);
  EXPECT_EQ(g.k.value(), 3.5);
  EXPECT_EQ(g.k.valueText(), "3.5");
}

TEST(Property, ByNameGetAndSetForSeveralTypes) {
  Gain g;
  g.setProperty("k", 4.0);
  EXPECT_EQ(g.getProperty<double>("k"), 4.0);
  g.setProperty("steps", 7);
  EXPECT_EQ(g.getProperty<int>("steps"), 7);
  g.setProperty("label", "fast");  // const char* accepted for a string
  EXPECT_EQ(g.getProperty<std::string>("label"), "fast");
  g.setProperty("enabled", false);
  EXPECT_FALSE(g.getProperty<bool>("enabled"));
  g.setProperty("offset", std::vector<double>{1.0, 2.0, 3.0});
  EXPECT_EQ(g.getProperty<std::vector<double>>("offset"), (std::vector<double>{1.0, 2.0, 3.0}));
}

TEST(Property, IntIsAcceptedForADouble) {
  Gain g;
  g.setProperty("k", 3);
  EXPECT_EQ(g.k.get(), 3.0);
}

TEST(Property, SetFromTextParsesWithTheTypesTextForm) {
  Gain g;
  g.property("k").setFromText("-1.25");
  EXPECT_EQ(g.k.get(), -1.25);
  g.property("offset").setFromText("[0.5, 1, 1.5]");
  EXPECT_EQ(g.offset.get(), (std::vector<double>{0.5, 1.0, 1.5}));
  g.property("tool").setFromText("[1, 2, 3, 0, 0, 0, 1]");
  EXPECT_EQ(g.tool.get().p, KDL::Vector(1, 2, 3));
  EXPECT_EQ(g.property("tool").valueText(), "[1, 2, 3, 0, 0, 0, 1]");
  g.property("enabled").setFromText("false");
  EXPECT_EQ(g.property("enabled").valueText(), "false");
}

TEST(Property, UnknownPropertyListsTheExistingOnes) {
  Gain g;
  const std::string msg = messageOf([&] { g.setProperty("gain", 1.0); });
  EXPECT_CONTAINS(msg, "component 'Gain' has no property 'gain'");
  EXPECT_CONTAINS(msg, "its properties are: k, steps, label, status, enabled, offset, tool");
  EXPECT_CONTAINS(messageOf([&] { (void)g.getProperty<double>("nope"); }), "has no property 'nope'");
  EXPECT_EQ(g.findProperty("nope"), nullptr);
  EXPECT_EQ(g.findProperty("k"), &g.k);
}

// --- refusals ---------------------------------------------------------------------------------

TEST(Property, OutOfRangeIsRefusedNamingComponentPropertyValueAndRange) {
  Gain g("Amp");
  const std::string msg = messageOf([&] { g.setProperty("k", 12.5); });
  EXPECT_CONTAINS(msg, "component 'Amp'");
  EXPECT_CONTAINS(msg, "property 'k'");
  EXPECT_CONTAINS(msg, "12.5");
  EXPECT_CONTAINS(msg, "[-10, 10]");
  EXPECT_EQ(g.k.get(), 2.0) << "a refused set leaves the value unchanged";
  const std::string int_msg = messageOf([&] { g.steps.set(0); });
  EXPECT_CONTAINS(int_msg, "property 'steps' = 0 is out of range [1, 100]");
  EXPECT_EQ(g.steps.get(), 5);
}

TEST(Property, CheckTextReportsTheErrorOfSetFromTextWithoutChangingAnything) {
  Gain g("Amp");
  PropertyBase& k = g.property("k");
  EXPECT_NO_THROW(k.checkText("3"));
  EXPECT_EQ(messageOf([&] { k.checkText("12"); }), messageOf([&] { k.setFromText("12"); }));
  EXPECT_CONTAINS(messageOf([&] { k.checkText("fast"); }), "cannot set it from \"fast\"; expected a number");
  EXPECT_CONTAINS(messageOf([&] { g.property("status").checkText("1"); }), "is read-only");
  EXPECT_EQ(g.k.get(), 2.0);
}

TEST(Property, RangeBoundsAreInclusive) {
  Gain g;
  g.k.set(-10.0);
  EXPECT_EQ(g.k.get(), -10.0);
  g.k.set(10.0);
  EXPECT_EQ(g.k.get(), 10.0);
}

TEST(Property, NanIsRefusedByARange) {
  Gain g;
  const std::string msg = messageOf([&] { g.k.set(std::numeric_limits<double>::quiet_NaN()); });
  EXPECT_CONTAINS(msg, "out of range");
  EXPECT_EQ(g.k.get(), 2.0);
  EXPECT_CONTAINS(messageOf([&] { g.property("k").setFromText("nan"); }), "out of range");
  EXPECT_EQ(g.k.get(), 2.0);
  Property<double> unbounded{"unbounded", 0.0, "1", "no range"};
  unbounded.set(std::numeric_limits<double>::quiet_NaN());
  EXPECT_TRUE(std::isnan(unbounded.get())) << "without a range NaN is a value like any other";
}

TEST(Property, BadRangesAreRefused) {
  Property<double> p{"p", 5.0, "m", ""};
  EXPECT_CONTAINS(messageOf([&] { p.range(1.0, 0.0); }), "range [1, 0] is empty");
  EXPECT_CONTAINS(messageOf([&] { p.range(0.0, 1.0); }), "initial value 5 is outside [0, 1]");
}

TEST(Property, ReadOnlyIsRefusedButTheOwnerCanWrite) {
  Gain g;
  const std::string msg = messageOf([&] { g.setProperty("status", 1.0); });
  EXPECT_CONTAINS(msg, "component 'Gain': property 'status' is read-only");
  EXPECT_CONTAINS(messageOf([&] { g.property("status").setFromText("1"); }), "is read-only");
  EXPECT_EQ(g.status.get(), 0.0);
  g.status.setFromOwner(42.0);
  EXPECT_EQ(g.getProperty<double>("status"), 42.0);
}

TEST(Property, WrongTypeIsRefusedNamingBothTypes) {
  Gain g;
  const std::string msg = messageOf([&] { g.setProperty("k", std::string("fast")); });
  EXPECT_CONTAINS(msg, "component 'Gain': property 'k' is a double: cannot set it from a string");
  EXPECT_CONTAINS(msg, "expected a number");
  EXPECT_CONTAINS(messageOf([&] { g.setProperty("steps", 2.5); }), "is a int: cannot set it from a double");
  EXPECT_CONTAINS(messageOf([&] { (void)g.getProperty<int>("k"); }), "property 'k' is a double, not a int");
  EXPECT_EQ(g.k.get(), 2.0);
  EXPECT_EQ(g.steps.get(), 5);
}

TEST(Property, UnparsableTextIsRefusedWithTheExpectedForm) {
  Gain g;
  const std::string msg = messageOf([&] { g.property("k").setFromText("fast"); });
  EXPECT_CONTAINS(msg, "property 'k' is a double: cannot set it from \"fast\"; expected a number, e.g. 1.5");
  EXPECT_CONTAINS(messageOf([&] { g.property("tool").setFromText("[0, 0, 0, 0, 0, 0, 2]"); }), "unit quaternion");
  EXPECT_EQ(g.k.get(), 2.0);
  EXPECT_EQ(g.tool.get(), KDL::Frame::Identity());
}

// --- running components -------------------------------------------------------------------------

/// Records the (a, b) pair seen by every update; a and b are always set together.
class PairRecorder : public Component {
 public:
  PairRecorder() : Component("Pair", Role::Calculation, "records pairs") {
    addProperty(a);
    addProperty(b);
    addOperation("setBoth", std::function<void(double, double)>([this](double x, double y) {
                   a.set(x);
                   b.set(y);
                 }),
                 "sets a and b in one operation");
    seen.reserve(kCapacity);
  }
  static constexpr std::size_t kCapacity = 1 << 16;
  Property<double> a{"a", 0.0, "1", "first"};
  Property<double> b{"b", 0.0, "1", "second"};
  std::vector<std::pair<double, double>> seen;  // read only after stop()

 protected:
  void updateHook() override {
    if (seen.size() < kCapacity) seen.emplace_back(a.get(), b.get());
  }
};

TEST(Property, SettingOnARunningPeriodicComponentTakesEffectBeforeSetReturns) {
  Gain g;
  g.setActivity(std::make_unique<PeriodicActivity>(500us, 0, Scheduler::Other));
  ASSERT_TRUE(g.configure());
  ASSERT_TRUE(g.start());
  ASSERT_TRUE(waitUntil([&] { return g.updateCount() > 0; }));
  for (int i = 0; i < 20; ++i) {
    const double k = -5.0 + 0.5 * i;
    g.k.set(k);
    EXPECT_EQ(g.k.value(), k);
    EXPECT_EQ(g.k.get(), k);
    g.setProperty("steps", i + 1);
    EXPECT_EQ(g.getProperty<int>("steps"), i + 1);
  }
  EXPECT_CONTAINS(messageOf([&] { g.k.set(11.0); }), "out of range");
  EXPECT_EQ(g.k.value(), 4.5);
  ASSERT_TRUE(g.stop());
}

TEST(Property, TwoPropertiesSetInOneOperationAreNeverSeenHalfApplied) {
  PairRecorder p;
  p.setActivity(std::make_unique<PeriodicActivity>(200us, 0, Scheduler::Other));
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  ASSERT_TRUE(waitUntil([&] { return p.updateCount() > 0; }));
  // 150 operation calls and 150 direct runBetweenSteps changes, alternating.
  for (int i = 1; i <= 150; ++i) {
    p.call("setBoth", 2.0 * i, 2.0 * i);
    p.runBetweenSteps([&] {
      p.a.set(2.0 * i + 1);
      p.b.set(2.0 * i + 1);
    });
    EXPECT_EQ(p.a.value(), 2.0 * i + 1);
    EXPECT_EQ(p.b.value(), 2.0 * i + 1);
  }
  ASSERT_TRUE(p.stop());
  ASSERT_FALSE(p.seen.empty());
  std::size_t distinct = 0;
  double last = -1.0;
  for (const auto& [a, b] : p.seen) {
    ASSERT_EQ(a, b) << "an update saw a half-applied pair";
    if (a != last) ++distinct;
    last = a;
  }
  EXPECT_GT(distinct, 1U) << "updates saw the changes";
}

TEST(Property, ARefusedSetOnARunningComponentChangesNothing) {
  Gain g;
  g.setActivity(std::make_unique<EventActivity>(0, Scheduler::Other));
  ASSERT_TRUE(g.configure());
  ASSERT_TRUE(g.start());
  EXPECT_THROW(g.setProperty("k", 100.0), Error);
  EXPECT_THROW(g.setProperty("status", 1.0), Error);
  EXPECT_EQ(g.k.value(), 2.0);
  g.setProperty("k", 1.0);  // and the component still takes changes
  EXPECT_EQ(g.k.value(), 1.0);
  ASSERT_TRUE(g.stop());
}

}  // namespace
}  // namespace cobra::core
