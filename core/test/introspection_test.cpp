// Unit tests of introspection (introspection.hpp): describe() snapshots, their text form, and
// the ComponentRegistry that owns components by name.

#include <gtest/gtest.h>

#include "cobra/test_support/test_support.hpp"

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cobra/core/activity.hpp"
#include "cobra/core/introspection.hpp"

namespace cobra::core {
namespace {

using cobra::test_support::messageOf;

class Adder : public Component {
 public:
  explicit Adder(std::string name) : Component(std::move(name), Role::Calculation, "adds an offset") {
    addEventPort(in);
    addPort(ref);
    addPort(out);
    addProperty(offset.range(-1.0, 1.0));
    addProperty(count.readOnly());
    addProperty(label);
    addOperation("add", std::function<double(double, double)>([](double a, double b) { return a + b; }), "a + b")
        .arg("a", "m", "first")
        .arg("b", "m", "second");
    addOperation("reset", std::function<void()>([] {}), "forgets everything", ExecutionThread::Client);
  }
  InputPort<double> in{"in", "position", "m"};
  InputPort<Event> ref{"ref", "commands", ""};
  OutputPort<double> out{"out", "shifted position", "m"};
  Property<double> offset{"offset", 0.25, "m", "added to the input"};
  Property<int> count{"count", 3, "1", "samples seen"};
  Property<std::string> label{"label", "adder", "", "display name"};
};

const PortInfo* findPort(const ComponentInfo& info, const std::string& name) {
  for (const PortInfo& p : info.ports)
    if (p.name == name) return &p;
  return nullptr;
}

const PropertyInfo* findProperty(const ComponentInfo& info, const std::string& name) {
  for (const PropertyInfo& p : info.properties)
    if (p.name == name) return &p;
  return nullptr;
}

// --- describe ---------------------------------------------------------------------------------

TEST(Describe, ListsNameRoleDocStateAndActivity) {
  Adder a("A");
  ComponentInfo info = describe(a);
  EXPECT_EQ(info.name, "A");
  EXPECT_EQ(info.role, Role::Calculation);
  EXPECT_EQ(info.doc, "adds an offset");
  EXPECT_EQ(info.state, State::PreOperational);
  EXPECT_EQ(info.activity, "slave");
  EXPECT_EQ(info.last_error, "");
  ASSERT_TRUE(a.configure());
  a.setActivity(std::make_unique<PeriodicActivity>(std::chrono::milliseconds(2), 0, Scheduler::Other));
  info = describe(a);
  EXPECT_EQ(info.state, State::Stopped);
  EXPECT_EQ(info.activity, "periodic 2 ms, SCHED_OTHER");
}

TEST(Describe, ListsPortsWithDirectionTypeUnitKindAndEventFlag) {
  Adder a("A");
  const ComponentInfo info = describe(a);
  ASSERT_EQ(info.ports.size(), 4U);
  EXPECT_EQ(info.ports[0].name, "events");  // every component has it, first
  const PortInfo* in = findPort(info, "in");
  ASSERT_NE(in, nullptr);
  EXPECT_EQ(in->direction, PortDirection::Input);
  EXPECT_EQ(in->type, "double");
  EXPECT_EQ(in->kind, DataKind::Pure);
  EXPECT_EQ(in->unit, "m");
  EXPECT_EQ(in->doc, "position");
  EXPECT_TRUE(in->event_port);
  const PortInfo* ref = findPort(info, "ref");
  ASSERT_NE(ref, nullptr);
  EXPECT_EQ(ref->type, "Event");
  EXPECT_EQ(ref->kind, DataKind::Logic);
  EXPECT_FALSE(ref->event_port);
  const PortInfo* out = findPort(info, "out");
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(out->direction, PortDirection::Output);
  EXPECT_TRUE(out->connections.empty());
}

TEST(Describe, ListsConnectedPeersWithTheirPolicy) {
  Adder a("A");
  Adder b("B");
  Adder c("C");
  connect(a.out, b.in, ConnPolicy::buffer(8));
  connect(a.out, c.in, ConnPolicy::circular(4));
  connect(a.events(), b.ref);
  const ComponentInfo ia = describe(a);
  const PortInfo* out = findPort(ia, "out");
  ASSERT_NE(out, nullptr);
  ASSERT_EQ(out->connections.size(), 2U);
  EXPECT_EQ(out->connections[0].peer, "B.in");
  EXPECT_EQ(out->connections[0].policy, "buffer(8)");
  EXPECT_EQ(out->connections[1].peer, "C.in");
  EXPECT_EQ(out->connections[1].policy, "circular(4)");
  const ComponentInfo ib = describe(b);
  const PortInfo* in = findPort(ib, "in");
  ASSERT_EQ(in->connections.size(), 1U);
  EXPECT_EQ(in->connections[0].peer, "A.out");
  EXPECT_EQ(findPort(ib, "ref")->connections[0].peer, "A.events");
  EXPECT_EQ(findPort(ib, "ref")->connections[0].policy, "data");
}

TEST(Describe, ListsPropertiesWithValueUnitRangeAndReadOnly) {
  Adder a("A");
  a.offset.set(-0.5);
  const ComponentInfo info = describe(a);
  ASSERT_EQ(info.properties.size(), 3U);
  const PropertyInfo* offset = findProperty(info, "offset");
  ASSERT_NE(offset, nullptr);
  EXPECT_EQ(offset->type, "double");
  EXPECT_EQ(offset->value, "-0.5");
  EXPECT_EQ(offset->unit, "m");
  EXPECT_EQ(offset->doc, "added to the input");
  EXPECT_EQ(offset->range, "[-1, 1]");
  EXPECT_FALSE(offset->read_only);
  const PropertyInfo* count = findProperty(info, "count");
  EXPECT_EQ(count->value, "3");
  EXPECT_TRUE(count->read_only);
  EXPECT_EQ(count->range, "");
  EXPECT_EQ(findProperty(info, "label")->value, "adder");
}

TEST(Describe, ListsOperationsWithSignatures) {
  Adder a("A");
  const ComponentInfo info = describe(a);
  ASSERT_EQ(info.operations.size(), 2U);
  EXPECT_EQ(info.operations[0].name, "add");
  EXPECT_EQ(info.operations[0].signature, "double add(double a [m], double b [m])");
  EXPECT_EQ(info.operations[0].doc, "a + b");
  EXPECT_EQ(info.operations[0].thread, ExecutionThread::Own);
  EXPECT_EQ(info.operations[1].signature, "void reset()");
  EXPECT_EQ(info.operations[1].thread, ExecutionThread::Client);
}

TEST(Describe, ReportsTheLastError) {
  class Broken : public Component {
   public:
    Broken() : Component("Broken", Role::Bridge, "") {}

   protected:
    bool configureHook() override { throw std::runtime_error("no device"); }
  };
  Broken b;
  (void)b.configure();
  const ComponentInfo info = describe(b);
  EXPECT_EQ(info.state, State::Exception);
  EXPECT_CONTAINS(info.last_error, "configureHook threw: no device");
  EXPECT_CONTAINS(toText(info), "last error: component 'Broken': configureHook threw: no device");
  EXPECT_CONTAINS(toText(info), "Broken [Bridge, Exception, slave]");
}

TEST(Describe, ToTextContainsEverything) {
  Adder a("A");
  Adder b("B");
  connect(a.out, b.in, ConnPolicy::buffer(8));
  const std::string text = toText(describe(a));
  EXPECT_CONTAINS(text, "A [Calculation, PreOperational, slave]");
  EXPECT_CONTAINS(text, "adds an offset");
  EXPECT_CONTAINS(text, "in(event) in : double [m]");
  EXPECT_CONTAINS(text, "ref : Event");
  EXPECT_CONTAINS(text, "out : double [m] -> B.in (buffer(8))");
  EXPECT_CONTAINS(text, "events : Event");
  EXPECT_CONTAINS(text, "property  offset : double = 0.25 [m] in [-1, 1]");
  EXPECT_CONTAINS(text, "property  count : int = 3 [1] (read-only)");
  EXPECT_CONTAINS(text, "operation double add(double a [m], double b [m])  -- a + b");
  EXPECT_CONTAINS(toText(describe(b)), "in : double [m] <- A.out (buffer(8))");
}

// --- ComponentRegistry ------------------------------------------------------------------------

TEST(ComponentRegistry, AddMakeGetFind) {
  ComponentRegistry registry;
  Adder& a = registry.make<Adder>("A");
  Component& b = registry.add(std::make_unique<Adder>("B"));
  EXPECT_EQ(&registry.get("A"), &a);
  EXPECT_EQ(registry.find("B"), &b);
  EXPECT_EQ(registry.find("C"), nullptr);
  EXPECT_EQ(registry.components(), (std::vector<Component*>{&a, &b}));
  const auto infos = registry.describeAll();
  ASSERT_EQ(infos.size(), 2U);
  EXPECT_EQ(infos[0].name, "A");
  EXPECT_EQ(infos[1].name, "B");
}

TEST(ComponentRegistry, DuplicateNamesAreRefused) {
  ComponentRegistry registry;
  registry.make<Adder>("A");
  EXPECT_EQ(messageOf([&] { registry.make<Adder>("A"); }), "a component named 'A' already exists; names must be unique");
  EXPECT_EQ(registry.components().size(), 1U);
  EXPECT_CONTAINS(messageOf([&] { registry.add(nullptr); }), "needs a component");
}

TEST(ComponentRegistry, UnknownNameListsTheKnownOnes) {
  ComponentRegistry registry;
  EXPECT_EQ(messageOf([&] { registry.get("X"); }), "no component named 'X'; the components are: (none)");
  registry.make<Adder>("A");
  registry.make<Adder>("B");
  EXPECT_EQ(messageOf([&] { registry.get("X"); }), "no component named 'X'; the components are: A, B");
}

TEST(ComponentRegistry, RemoveStopsDisconnectsAndDestroys) {
  ComponentRegistry registry;
  Adder& a = registry.make<Adder>("A");
  Adder& b = registry.make<Adder>("B");
  b.setActivity(std::make_unique<EventActivity>(0, Scheduler::Other));
  connect(a.out, b.in);
  connect(b.out, a.in);
  ASSERT_TRUE(b.configure());
  ASSERT_TRUE(b.start());
  EXPECT_TRUE(registry.remove("B"));
  EXPECT_FALSE(registry.remove("B"));
  EXPECT_EQ(registry.find("B"), nullptr);
  EXPECT_FALSE(a.out.connected());
  EXPECT_FALSE(a.in.connected());
  EXPECT_EQ(a.out.write(1.0), WriteStatus::NotConnected);
}

TEST(ComponentRegistry, DestructionStopsRunningComponents) {
  auto registry = std::make_unique<ComponentRegistry>();
  Adder& a = registry->make<Adder>("A");
  Adder& b = registry->make<Adder>("B");
  a.setActivity(std::make_unique<PeriodicActivity>(std::chrono::milliseconds(1), 0, Scheduler::Other));
  connect(a.out, b.in);
  ASSERT_TRUE(a.configure());
  ASSERT_TRUE(a.start());
  registry.reset();  // must not hang or crash
  SUCCEED();
}

}  // namespace
}  // namespace cobra::core
