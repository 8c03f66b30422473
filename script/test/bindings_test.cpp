// Lua access to components: properties, operations, lifecycle, ports, descriptions, unknown
// names, the text fallback for types without a conversion, and getReferences.

#include "cobra/script/bindings.hpp"

#include <gtest/gtest.h>

#include <kdl/frames.hpp>

#include "cobra/core/core.hpp"
#include "cobra/test_support/test_support.hpp"

// A type registered by "another module", with no Lua conversion: it travels as text.
struct Gripper {
  double opening = 0.0;  // m
};
template <>
struct cobra::core::DataTypeTraits<Gripper> {
  static constexpr std::string_view name = "test.Gripper";
  static constexpr DataKind kind = DataKind::Pure;
  static constexpr std::string_view format = "'open <m>'";
  static std::string print(const Gripper& g) { return "open " + printValue(g.opening); }
  static bool parse(std::string_view text, Gripper& out) {
    if (text.substr(0, 5) != "open ") return false;
    return DataTypeTraits<double>::parse(text.substr(5), out.opening);
  }
};

namespace cobra::script {
namespace {

using core::Role;

class Planner : public core::Component {
 public:
  explicit Planner(std::string name) : Component(std::move(name), Role::Calculation, "test planner") {
    addPort(u_);
    addPort(y_);
    addPort(goal_);
    addPort(gripper_out_);
    addProperty(max_vel_.range(0.0, 1.0));
    addProperty(count_);
    addProperty(target_);
    addProperty(status_.readOnly());
    addProperty(gripper_);
    addOperation("add", std::function<double(double, double)>([](double a, double b) { return a + b; }), "a + b")
        .arg("a", "1", "first")
        .arg("b", "1", "second");
    addOperation("askStartMove", &Planner::askStartMove, this, "starts a move; answers with an event");
    addOperation("fail", std::function<void()>([] { throw std::runtime_error("planner broke"); }), "always fails");
    addOperation("widen", std::function<Gripper(Gripper, double)>([](Gripper g, double d) {
                   g.opening += d;
                   return g;
                 }),
                 "opens a gripper further");
  }
  int moves = 0;
  core::InputPort<double>& u() { return u_; }

 private:
  void askStartMove() { ++moves; }
  core::InputPort<double> u_{"u", "input", "1"};
  core::OutputPort<double> y_{"y", "output", "1"};
  core::OutputPort<KDL::Frame> goal_{"goal", "goal pose", "m"};
  core::OutputPort<Gripper> gripper_out_{"gripper_out", "gripper command", "m"};
  core::Property<double> max_vel_{"max_vel", 0.5, "m/s", "maximum velocity"};
  core::Property<int> count_{"count", 3, "1", "a count"};
  core::Property<KDL::Vector> target_{"target", KDL::Vector(1, 2, 3), "m", "target position"};
  core::Property<std::string> status_{"status", "idle", "", "what it does"};
  core::Property<Gripper> gripper_{"gripper", Gripper{0.01}, "m", "gripper"};
};

class Bindings : public testing::Test {
 protected:
  Bindings() { exposeComponent(lua, planner); }

  /// The error running `code` (chunk name "test") throws, or "(no error)".
  std::string luaError(const std::string& code) {
    return test_support::messageOf([&] { lua.run(code, "=test"); });
  }

  Planner planner{"P"};
  LuaState lua;
};

TEST_F(Bindings, ReadsProperties) {
  EXPECT_EQ(lua.evaluate("P.max_vel"), "0.5");
  EXPECT_EQ(lua.evaluate("math.type(P.count)"), "integer");
  EXPECT_EQ(lua.evaluate("P.target.y"), "2.0");
  EXPECT_EQ(lua.evaluate("P.status"), "idle");
}

TEST_F(Bindings, SetsProperties) {
  lua.run("P.max_vel = 0.2; P.count = 7; P.target = {4, 5, 6}");
  EXPECT_EQ(planner.getProperty<double>("max_vel"), 0.2);
  EXPECT_EQ(planner.getProperty<int>("count"), 7);
  EXPECT_EQ(planner.getProperty<KDL::Vector>("target"), KDL::Vector(4, 5, 6));
}

TEST_F(Bindings, RefusedPropertySetsCarryTheCoreMessageAndChangeNothing) {
  EXPECT_EQ(luaError("P.max_vel = 2"), "test:1: component 'P': property 'max_vel' = 2 is out of range [0, 1] (m/s)");
  EXPECT_EQ(luaError("P.max_vel = 'fast'"),
            "test:1: component 'P': property 'max_vel' is a double: cannot set it from Lua: expected a number, got "
            "the string \"fast\"");
  EXPECT_EQ(luaError("P.count = 1.5"),
            "test:1: component 'P': property 'count' is a int: cannot set it from Lua: expected an integer, got the "
            "number 1.5 (not an integer)");
  EXPECT_EQ(luaError("P.status = 'busy'"), "test:1: component 'P': property 'status' is read-only; it reports a value "
                                          "and cannot be set");
  EXPECT_EQ(luaError("P.nope = 1"),
            "test:1: component 'P' has no property 'nope'; its properties are: max_vel, count, target, status, gripper");
  EXPECT_EQ(luaError("P.u = 1"), "test:1: component 'P': 'u' is a port; only properties can be assigned");
  EXPECT_EQ(planner.getProperty<double>("max_vel"), 0.5);
  EXPECT_EQ(planner.getProperty<int>("count"), 3);
}

TEST_F(Bindings, UnknownNamesListWhatExists) {
  EXPECT_EQ(luaError("local x = P.nope"),
            "test:1: component 'P' has no port, property or operation 'nope'; its ports are: events, u, y, goal, gripper_out; its "
            "properties are: max_vel, count, target, status, gripper; its operations are: add, askStartMove, fail, "
            "widen; its methods are: configure, start, stop, cleanup, recover, getState, getName, getRole, "
            "getLastError, now, emitEvent");
  EXPECT_EQ(luaError("local x = P[1]"), "test:1: component 'P': index it with a name (a string), not the integer 1");
}

TEST_F(Bindings, CallsOperations) {
  EXPECT_EQ(lua.evaluate("P:add(1, 2.5)"), "3.5");
  EXPECT_EQ(lua.evaluate("P.add(1, 2)"), "3.0");
  lua.run("P:askStartMove() P.askStartMove()");
  EXPECT_EQ(planner.moves, 2);
  EXPECT_EQ(lua.evaluate("select('#', P:askStartMove())"), "0");
}

TEST_F(Bindings, OperationErrorsNameTheSignatureAndArgument) {
  EXPECT_EQ(luaError("P:add(1)"), "test:1: component 'P': operation 'double add(double a [1], double b [1])' expects "
                                 "2 argument(s), got 1");
  EXPECT_EQ(luaError("P:add(1, 'x')"),
            "test:1: component 'P': operation 'double add(double a [1], double b [1])': argument 2 ('b') must be a "
            "double: expected a number, got the string \"x\"");
  EXPECT_EQ(luaError("P:fail()"), "test:1: component 'P': operation 'void fail()' failed: planner broke");
}

TEST_F(Bindings, LifecycleFromLua) {
  lua.run("assert(P:getState() == 'PreOperational') assert(P:configure()) assert(P:start())");
  EXPECT_EQ(planner.state(), core::State::Running);
  EXPECT_EQ(luaError("P:start()"), "test:1: component 'P': cannot start: it is Running; it is already running");
  lua.run("assert(P:stop()) assert(P:cleanup())");
  EXPECT_EQ(lua.evaluate("P:getState()"), "PreOperational");
  EXPECT_EQ(lua.evaluate("P:getName() .. ' ' .. P:getRole()"), "P Calculation");
  EXPECT_EQ(luaError("P:recover()"),
            "test:1: component 'P': cannot recover: it is PreOperational; only a component in Exception can recover");
  EXPECT_EQ(luaError("P.start()"), "test:1: call component methods with ':' (Comp:start()), not '.' (Comp.start())");
}

TEST_F(Bindings, TimeAndEvents) {
  core::InputPort<core::Event> events{"events_in", "", ""};
  core::connectPorts(planner.events(), events);
  core::LockstepClock clock;
  clock.add(planner, std::chrono::milliseconds(1));
  clock.advance(std::chrono::milliseconds(1500));
  EXPECT_EQ(lua.evaluate("P:now()"), "1.5");
  lua.run("P:emitEvent('e_plan_done')");
  core::Event e;
  ASSERT_EQ(events.read(e), core::FlowStatus::NewData);
  EXPECT_EQ(e.name, "e_plan_done");
  EXPECT_EQ(e.source, "P");
  EXPECT_EQ(luaError("P:emitEvent(3)"), "test:1: component 'P': emitEvent takes an event name (a string), got the integer 3");
}

TEST_F(Bindings, DescribesTheComponent) {
  EXPECT_EQ(lua.evaluate("P()"), core::toText(core::describe(planner)));
  EXPECT_NE(lua.evaluate("P").find("max_vel"), std::string::npos);
}

TEST_F(Bindings, PortsReadAndWrite) {
  EXPECT_EQ(lua.evaluate("P.y:name() .. ' ' .. P.y:type() .. ' ' .. P.y:unit() .. ' ' .. P.y:doc()"), "y double 1 output");
  EXPECT_EQ(lua.evaluate("P.y:connected()"), "false");
  core::InputPort<double> sink{"sink", "", "1"};
  core::connectPorts(planner.port("y"), sink);
  core::OutputPort<double> source{"source", "", "1"};
  core::connect(source, planner.u());
  EXPECT_EQ(lua.evaluate("P.y:connected()"), "true");
  EXPECT_EQ(lua.evaluate("P.y == P.y"), "true");  // one object per port
  EXPECT_EQ(lua.evaluate("select(1, P.u:read())"), "NoData");
  source.write(4.0);
  lua.run("fs, v = P.u:read() P.y:write(2 * v)");
  EXPECT_EQ(lua.evaluate("fs"), "NewData");
  double y = 0.0;
  EXPECT_EQ(sink.read(y), core::FlowStatus::NewData);
  EXPECT_EQ(y, 8.0);
  EXPECT_EQ(lua.evaluate("select(1, P.u:read())"), "OldData");
  EXPECT_EQ(lua.evaluate("tostring(P.u)"), "port P.u (double, input)");
}

TEST_F(Bindings, PortMisuseIsAnError) {
  EXPECT_EQ(luaError("P.u:write(1)"), "test:1: port P.u is an input port: only output ports can be written");
  EXPECT_EQ(luaError("P.goal:write({1, 2})"),
            "test:1: port P.goal is a KDL.Frame: cannot write it: expected {p = {x=, y=, z=}, M = {x=, y=, z=, w=}} or "
            "{x, y, z, qx, qy, qz, qw}, got a table (an array of 2 elements)");
  EXPECT_EQ(luaError("P.y.write(1)"), "test:1: call port methods with ':' (port:read()), not '.'");
}

TEST_F(Bindings, ReadsOutputPortsThroughAPrivateConnection) {
  EXPECT_EQ(lua.evaluate("select(1, P.y:read())"), "NoData");  // connects; nothing written since
  EXPECT_EQ(lua.evaluate("P.y:connected()"), "true");
  dynamic_cast<core::OutputPort<double>&>(planner.port("y")).write(3.0);
  lua.run("fs, v = P.y:read()");
  EXPECT_EQ(lua.evaluate("fs .. ' ' .. v"), "NewData 3.0");
  EXPECT_EQ(lua.evaluate("select(1, P.gripper_out:read())"), "NoData");
  dynamic_cast<core::OutputPort<Gripper>&>(planner.port("gripper_out")).write(Gripper{0.05});
  EXPECT_EQ(lua.evaluate("select(2, P.gripper_out:read())"), "open 0.05");
}

TEST_F(Bindings, WritesGeometry) {
  core::InputPort<KDL::Frame> sink{"sink", "", "m"};
  core::connectPorts(planner.port("goal"), sink);
  lua.run("P.goal:write({p = {x = 0.1, y = 0, z = 0.3}, M = {0, 0, 0, 1}})");
  KDL::Frame f;
  ASSERT_EQ(sink.read(f), core::FlowStatus::NewData);
  EXPECT_TRUE(KDL::Equal(f, KDL::Frame(KDL::Vector(0.1, 0, 0.3)), 1e-12));
}

TEST_F(Bindings, TypesWithoutConversionTravelAsText) {
  EXPECT_EQ(lua.evaluate("P.gripper"), "open 0.01");
  lua.run("P.gripper = 'open 0.02'");
  EXPECT_EQ(planner.property("gripper").valueText(), "open 0.02");
  EXPECT_EQ(luaError("P.gripper = 0.02"), "test:1: component 'P': property 'gripper' is a test.Gripper, which Lua sets "
                                         "from text: expected a string ('open <m>'), got the number 0.02");
  EXPECT_EQ(lua.evaluate("P:widen('open 0.02', 0.01)"), "open 0.03");
}

TEST(GetReferences, ExposesEveryComponentOfARegistry) {
  core::ComponentRegistry registry;
  registry.make<Planner>("TrajGen");
  registry.make<Planner>("MotPlan");
  LuaState lua;
  getReferences(lua, registry);
  lua.run("TrajGen.max_vel = 0.25 MotPlan:askStartMove()");
  EXPECT_EQ(registry.get("TrajGen").getProperty<double>("max_vel"), 0.25);
  EXPECT_EQ(static_cast<Planner&>(registry.get("MotPlan")).moves, 1);
  registry.make<Planner>("Later");
  EXPECT_EQ(lua.evaluate("Later"), "nil");
  lua.run("getReferences()");
  EXPECT_EQ(lua.evaluate("Later:getName()"), "Later");
}

}  // namespace
}  // namespace cobra::script
