// LuaComponent: a script doing real work on the lockstep clock, declarations, hook results,
// load and runtime errors with file:line, pool exhaustion, endless loops cut at their budget,
// recover and reload.

#include "cobra/script/lua_component.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <thread>

#include "cobra/core/core.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::script {
namespace {

using namespace std::chrono_literals;

/// Writes `code` to a fresh file and returns its path.
std::string writeScript(const std::string& name, const std::string& code) {
  const std::string path = ::cobra::test_support::scratchPath("lua_component_test_" + name + ".lua").string();
  std::ofstream(path) << code;
  return path;
}

const char* const kDoubler = R"(
self:addInputPort("u", "double", "signal u", "1")
self:addOutputPort("y", "double", "signal y = k u", "1")
self:addProperty("k", "double", 2.0, "1", "gain")
updates = 0
function configureHook() return self.k ~= 0 end
function updateHook()
  updates = updates + 1
  local fs, u = self.u:read()
  if fs == "NewData" then self.y:write(self.k * u) end
end
)";

TEST(LuaComponent, DoublesItsInputOnTheLockstepClock) {
  LuaComponent doubler("Doubler", core::Role::Calculation);
  doubler.setProperty("script_path", writeScript("doubler", kDoubler));
  doubler.loadScript();  // declares the ports, so they can be connected before configure
  core::OutputPort<double> source{"source", "", "1"};
  core::InputPort<double> sink{"sink", "", "1"};
  core::connectPorts(source, doubler.port("u"));
  core::connectPorts(doubler.port("y"), sink, core::ConnPolicy::buffer(16));
  core::LockstepClock clock;
  clock.add(doubler, 1ms);
  ASSERT_TRUE(doubler.configure());
  ASSERT_TRUE(doubler.start());
  for (int i = 1; i <= 5; ++i) {
    source.write(i * 0.5);
    clock.advance(1ms);
  }
  double y = 0.0;
  std::vector<double> seen;
  while (sink.read(y) == core::FlowStatus::NewData) seen.push_back(y);
  EXPECT_EQ(seen, (std::vector<double>{1, 2, 3, 4, 5}));
  doubler.setProperty("k", -1.0);  // applied between two updates
  source.write(3.0);
  clock.advance(1ms);
  sink.read(y);
  EXPECT_EQ(y, -3.0);
  EXPECT_EQ(doubler.lua()->evaluate("updates"), "6");
  EXPECT_TRUE(doubler.stop());
}

TEST(LuaComponent, SelfAndItsNameAreTheSameObject) {
  LuaComponent c("Named", core::Role::Decision);
  c.setProperty("script_path", writeScript("named", "assert(self == Named) name = self:getName()"));
  ASSERT_TRUE(c.configure());
  EXPECT_EQ(c.lua()->evaluate("name"), "Named");
  EXPECT_EQ(c.lua()->evaluate("self.lua_pool_size"), "262144");
}

TEST(LuaComponent, EventPortTriggersTheUpdate) {
  LuaComponent c("Counter", core::Role::Supervision);
  c.setProperty("script_path", writeScript("counter", R"(
self:addEventPort("events_in", "Event", "events to count", "")
self:addOutputPort("last", "string", "name of the last event", "")
function updateHook()
  local fs, e = self.events_in:read()
  if fs == "NewData" then self.last:write(e.name .. "@" .. e.source) end
end
)"));
  c.loadScript();
  core::OutputPort<core::Event> events{"events", "", ""};
  core::InputPort<std::string> last{"last_in", "", ""};
  core::connectPorts(events, c.port("events_in"));
  core::connectPorts(c.port("last"), last);
  core::LockstepClock clock;
  clock.add(c, 0ns);
  ASSERT_TRUE(c.configure());
  ASSERT_TRUE(c.start());
  events.write(core::Event{"e_done", "Planner", 0ns});
  clock.advance(1ms);
  std::string text;
  ASSERT_EQ(last.read(text), core::FlowStatus::NewData);
  EXPECT_EQ(text, "e_done@Planner");
}

TEST(LuaComponent, RunsOnItsOwnThread) {
  LuaComponent c("Threaded", core::Role::Calculation);
  c.setProperty("script_path", writeScript("threaded", R"(
self:addEventPort("u", "double", "input", "1")
self:addOutputPort("y", "double", "k u", "1")
self:addProperty("k", "double", 3.0, "1", "gain")
function updateHook()
  local fs, u = self.u:read()
  if fs == "NewData" then self.y:write(self.k * u) end
end
)"));
  c.loadScript();
  c.setActivity(std::make_unique<core::EventActivity>(50, core::Scheduler::Other));
  core::OutputPort<double> source{"source", "", "1"};
  core::InputPort<double> sink{"sink", "", "1"};
  core::connectPorts(source, c.port("u"));
  core::connectPorts(c.port("y"), sink);
  ASSERT_TRUE(c.configure());
  ASSERT_TRUE(c.start());
  c.setProperty("k", 4.0);  // applied between two updates of the activity thread
  source.write(2.5);
  double y = 0.0;
  // Waits for the activity thread (no timing assertion: the bound only keeps a bug from hanging).
  for (int i = 0; i < 20000 && sink.read(y) != core::FlowStatus::NewData; ++i) std::this_thread::sleep_for(100us);
  EXPECT_EQ(y, 10.0);
  EXPECT_TRUE(c.stop());
  EXPECT_EQ(c.state(), core::State::Stopped);
}

TEST(LuaComponent, HooksMayRefuse) {
  LuaComponent c("Picky", core::Role::Calculation);
  c.setProperty("script_path", writeScript("picky", kDoubler));
  c.loadScript();
  c.setProperty("k", 0.0);
  const core::Result result = c.configure();
  EXPECT_FALSE(result);
  EXPECT_EQ(result.message, "component 'Picky': configureHook refused the configuration");
  EXPECT_EQ(c.state(), core::State::PreOperational);
  c.setProperty("k", 1.0);
  EXPECT_TRUE(c.configure());
}

TEST(LuaComponent, MissingScriptPathSaysWhatIsNeeded) {
  LuaComponent c("NoScript", core::Role::Calculation);
  const core::Result result = c.configure();
  EXPECT_EQ(result.message, "component 'NoScript': configureHook threw: component 'NoScript': script_path is empty; "
                            "set it to the Lua file that defines the hooks");
}

TEST(LuaComponent, SyntaxErrorFailsConfigureWithFileAndLine) {
  LuaComponent c("Broken", core::Role::Calculation);
  const std::string path = writeScript("syntax", "function updateHook()\n  local x = \nend\n");
  c.setProperty("script_path", path);
  const core::Result result = c.configure();
  EXPECT_FALSE(result);
  EXPECT_EQ(result.message, "component 'Broken': configureHook threw: Lua script of component 'Broken' failed: " +
                                path + ":3: unexpected symbol near 'end'");
  EXPECT_EQ(c.lua(), nullptr);
}

TEST(LuaComponent, HookThatIsNotAFunctionIsRefused) {
  LuaComponent c("Odd", core::Role::Calculation);
  const std::string path = writeScript("odd", "updateHook = 42\n");
  c.setProperty("script_path", path);
  EXPECT_EQ(c.configure().message, "component 'Odd': configureHook threw: Lua script of component 'Odd' (" + path +
                                       "): the global 'updateHook' must be a function (or nil)");
}

TEST(LuaComponent, RuntimeErrorInUpdateHookIsAnExceptionWithFileAndLine) {
  LuaComponent c("Faulty", core::Role::Calculation);
  const std::string path = writeScript("faulty", R"(n = 0
function updateHook()
  n = n + 1
  if n == 3 then
    local v = undefined_thing + 1
  end
end
function exceptionHook() handled = n end
function cleanupHook() end
)");
  c.setProperty("script_path", path);
  core::LockstepClock clock;
  clock.add(c, 1ms);
  ASSERT_TRUE(c.configure());
  ASSERT_TRUE(c.start());
  clock.advance(10ms);
  EXPECT_EQ(c.state(), core::State::Exception);
  EXPECT_EQ(c.lastError(), "component 'Faulty': updateHook threw: " + path +
                               ":5: attempt to perform arithmetic on a nil value (global 'undefined_thing')");
  EXPECT_EQ(c.lua()->evaluate("handled"), "3");
  ASSERT_TRUE(c.recover());
  EXPECT_EQ(c.lua(), nullptr);  // recover closes the state; configure loads the script again
  ASSERT_TRUE(c.configure());
  EXPECT_EQ(c.lua()->evaluate("n"), "0");
}

TEST(LuaComponent, PoolExhaustionIsAClearErrorNotACrash) {
  LuaComponent c("Hog", core::Role::Calculation);
  c.setProperty("script_path", writeScript("hog", R"(
kept = {}
function updateHook() kept[#kept + 1] = string.rep("x", 1000) .. #kept end
)"));
  c.setProperty("lua_pool_size", 128 * 1024);
  core::LockstepClock clock;
  clock.add(c, 1ms);
  ASSERT_TRUE(c.configure());
  ASSERT_TRUE(c.start());
  clock.advance(1s);
  EXPECT_EQ(c.state(), core::State::Exception);
  EXPECT_EQ(c.lastError(), "component 'Hog': updateHook threw: Lua memory pool of component 'Hog' exhausted "
                           "(128 KiB); raise its lua_pool_size property");
  ASSERT_TRUE(c.recover());
  c.setProperty("lua_pool_size", 4096);
  EXPECT_EQ(c.configure().message, "component 'Hog': configureHook threw: Lua memory pool of component 'Hog' (4 KiB) "
                                   "is too small to create a Lua state; raise its lua_pool_size property");
}

const char* const kSpinner = R"(n = 0
function updateHook()
  n = n + 1
  if n == 3 then
    while true do n = n + 1 end
  end
end
)";

TEST(LuaComponent, AnEndlessLoopInAHookIsCutAtItsBudgetAndTheOthersKeepTheirPeriod) {
  LuaComponent c("Spinner", core::Role::Calculation);
  const std::string path = writeScript("spinner", kSpinner);
  c.setProperty("script_path", path);
  core::Component ticker("Ticker", core::Role::Calculation, "counts its updates");
  core::LockstepClock clock;
  clock.add(c, 1ms);
  clock.add(ticker, 1ms);
  ASSERT_TRUE(c.configure());
  ASSERT_TRUE(c.start());
  ASSERT_TRUE(ticker.configure());
  ASSERT_TRUE(ticker.start());
  clock.advance(10ms);
  EXPECT_EQ(c.state(), core::State::Exception);
  EXPECT_EQ(c.lastError(), "component 'Spinner': updateHook threw: " + path +
                               ":5: component 'Spinner' ran past its budget of 0.005 s of CPU time; raise its "
                               "lua_budget property if the hook needs that long");
  EXPECT_EQ(c.updateCount(), 2u);      // the third update threw
  EXPECT_EQ(ticker.updateCount(), 10u);  // every period of the 10 ms
}

TEST(LuaComponent, AnEndlessLoopOnItsOwnThreadIsCutAtItsBudget) {
  LuaComponent c("ThreadSpinner", core::Role::Calculation);
  const std::string path = writeScript("thread_spinner", kSpinner);
  c.setProperty("script_path", path);
  c.setProperty("lua_budget", 0.005);
  c.setActivity(std::make_unique<core::PeriodicActivity>(1ms, 0, core::Scheduler::Other));
  ASSERT_TRUE(c.configure());
  ASSERT_TRUE(c.start());
  // Waits for the activity thread (the bound only keeps a bug from hanging the test).
  for (int i = 0; i < 100000 && c.state() != core::State::Exception; ++i) std::this_thread::sleep_for(100us);
  EXPECT_EQ(c.state(), core::State::Exception);
  EXPECT_EQ(c.lastError(), "component 'ThreadSpinner': updateHook threw: " + path +
                               ":5: component 'ThreadSpinner' ran past its budget of 0.005 s of CPU time; raise its "
                               "lua_budget property if the hook needs that long");
  EXPECT_TRUE(c.recover());
}

TEST(LuaComponent, AScriptLoopingAtLoadIsCutAtTheLoadBudget) {
  LuaComponent c("SlowLoad", core::Role::Calculation);
  const std::string path = writeScript("slow_load", "local n = 0\nwhile true do n = n + 1 end\n");
  c.setProperty("script_path", path);
  c.setProperty("lua_load_budget", 0.05);
  EXPECT_EQ(c.configure().message, "component 'SlowLoad': configureHook threw: Lua script of component 'SlowLoad' "
                                   "failed: " + path + ":2: component 'SlowLoad' ran past its budget of 0.05 s of "
                                   "CPU time; raise its lua_load_budget property");
}

TEST(LuaComponent, ReloadKeepsDeclaredPortsConnectionsAndValues) {
  LuaComponent c("Reload", core::Role::Calculation);
  c.setProperty("script_path", writeScript("reload", kDoubler));
  c.loadScript();
  core::InputPort<double> sink{"sink", "", "1"};
  core::connectPorts(c.port("y"), sink);
  c.setProperty("k", 5.0);
  ASSERT_TRUE(c.configure());
  ASSERT_TRUE(c.cleanup());
  ASSERT_TRUE(c.configure());  // runs the script again: same declarations
  EXPECT_EQ(c.getProperty<double>("k"), 5.0);
  EXPECT_TRUE(c.port("y").connectedTo(sink));
}

TEST(LuaComponent, DeclaredPropertiesMayHaveARange) {
  LuaComponent c("Ranged", core::Role::Calculation);
  c.setProperty("script_path", writeScript("ranged", "self:addProperty('k', 'double', 2.0, '1', 'gain', {min = 0, max = 5})\n"
                                                     "self:addProperty('n', 'int', 3, '1', 'count', {min = 1, max = 9})"));
  c.loadScript();
  try {
    c.setProperty("k", 6.0);
    ADD_FAILURE() << "out of range accepted";
  } catch (const core::Error& e) {
    EXPECT_STREQ(e.what(), "component 'Ranged': property 'k' = 6 is out of range [0, 5] (1)");
  }
  EXPECT_EQ(c.property("n").rangeText(), "[1, 9]");
  LuaComponent bad("BadRange", core::Role::Calculation);
  bad.setProperty("script_path", writeScript("bad_range", "self:addProperty('s', 'string', 'a', '', 'text', {min = 0, max = 1})"));
  EXPECT_NE(bad.configure().message.find("bad_range.lua:1: component 'BadRange': property 's' is a string: only double "
                                         "and int properties take a range"),
            std::string::npos);
}

TEST(LuaComponent, BadDeclarationsAreErrors) {
  LuaComponent c("Decl", core::Role::Calculation);
  c.setProperty("script_path", writeScript("decl_type", "self:addInputPort('u', 'quaternion')"));
  EXPECT_NE(c.configure().message.find(
                "decl_type.lua:1: component 'Decl': cannot declare port 'u' of type 'quaternion'; Lua can declare the "
                "types: double, int, bool, string, vector<double>, KDL.Vector"),
            std::string::npos);
  ASSERT_TRUE(c.recover());
  c.setProperty("script_path", writeScript("decl_twice", "self:addInputPort('u', 'double')\n"
                                                         "self:addOutputPort('u', 'double')"));
  EXPECT_NE(c.configure().message.find("decl_twice.lua:2: component 'Decl' already has a port 'u' (double input); "
                                       "the script declares it again differently"),
            std::string::npos);
  ASSERT_TRUE(c.recover());
  c.setProperty("script_path", writeScript("decl_value", "self:addProperty('n', 'int', 0.5)"));
  EXPECT_NE(c.configure().message.find("decl_value.lua:1: component 'Decl': property 'n' is a int: its initial value "
                                       "(argument 3) is wrong: expected an integer, got the number 0.5 (not an "
                                       "integer)"),
            std::string::npos);
}

}  // namespace
}  // namespace cobra::script
