// LuaState: running code, error messages with chunk:line, pools (too small, exhausted, usable
// again afterwards), the CPU-time budget and the interrupt flag cutting endless loops.

#include "cobra/script/lua_state.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <fstream>

#include "cobra/core/error.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::script {
namespace {

TEST(LuaState, RunsCodeWithTheStandardLibraries) {
  LuaState lua;
  lua.run("x = math.sqrt(16) + #string.rep('a', 3)");
  EXPECT_EQ(lua.evaluate("x"), "7.0");
  EXPECT_EQ(lua.pool(), nullptr);
}

TEST(LuaState, ErrorsCarryChunkNameAndLine) {
  LuaState lua;
  EXPECT_EQ(test_support::messageOf([&] { lua.run("local a = 1\nerror('boom')", "=setup"); }), "setup:2: boom");
  EXPECT_EQ(test_support::messageOf([&] { lua.run("x = = 1", "=setup"); }), "setup:1: unexpected symbol near '='");
  EXPECT_EQ(test_support::messageOf([&] { lua.run("local t = nil\nreturn t.x", "=setup"); }),
            "setup:2: attempt to index a nil value (local 't')");
}

TEST(LuaState, RunFileNamesTheFile) {
  const std::string path = ::cobra::test_support::scratchPath("lua_state_test_bad.lua").string();
  std::ofstream(path) << "local ok = true\nif ok then\n  error('in the file')\nend\n";
  LuaState lua;
  EXPECT_EQ(test_support::messageOf([&] { lua.runFile(path); }), path + ":3: in the file");
  EXPECT_EQ(test_support::messageOf([&] { lua.runFile("/nonexistent/x.lua"); }),
            "cannot open /nonexistent/x.lua: No such file or directory");
}

TEST(LuaState, PoolTooSmallForTheStandardLibrariesIsAClearError) {
  LuaMemory memory{4096, "component 'Tiny'", "raise its lua_pool_size property"};
  const std::string message = test_support::messageOf([&] { LuaState lua(memory); });
  EXPECT_NE(message.find("component 'Tiny'"), std::string::npos) << message;
  EXPECT_NE(message.find("4 KiB"), std::string::npos) << message;
  EXPECT_NE(message.find("raise its lua_pool_size property"), std::string::npos) << message;
}

TEST(LuaState, PoolExhaustionIsAnErrorAndTheStateStaysUsable) {
  LuaState lua({256 * 1024, "component 'X'", "raise its lua_pool_size property"});
  ASSERT_NE(lua.pool(), nullptr);
  EXPECT_EQ(test_support::messageOf([&] { lua.run("t = {} for i = 1, 1e7 do t[i] = {i} end"); }),
            "Lua memory pool of component 'X' exhausted (256 KiB); raise its lua_pool_size property");
  EXPECT_GT(lua.pool()->failures(), 0u);
  lua.run("t = nil collectgarbage()");
  EXPECT_EQ(lua.evaluate("1 + 1"), "2");
  EXPECT_LE(lua.pool()->peak(), lua.pool()->capacity());
}

TEST(LuaState, ErrorObjectsThatAreNotStringsAreDescribed) {
  LuaState lua;
  EXPECT_EQ(test_support::messageOf([&] { lua.run("error({})"); }), "Lua error with a table value as error object");
}

using namespace std::chrono_literals;

TEST(LuaState, AnEndlessLoopIsCutAtItsBudgetNamingTheLine) {
  LuaState lua({0, "component 'Looper'", ""});
  lua.setBudget(20ms, "raise its lua_budget property");
  lua.startStep();
  EXPECT_EQ(test_support::messageOf([&] { lua.run("local n = 0\nwhile true do\n  n = n + 1\nend", "=loop"); }).substr(0, 7), "loop:3:");
  lua.startStep();
  const std::string message = test_support::messageOf([&] { lua.run("local n = 0\nwhile true do n = n + 1 end", "=loop"); });
  EXPECT_EQ(message, "loop:2: component 'Looper' ran past its budget of 0.02 s of CPU time; raise its lua_budget property");
  // The next step runs normally: a budget is per step.
  lua.startStep();
  lua.run("x = 0 for i = 1, 1000 do x = x + i end");
  EXPECT_EQ(lua.evaluate("x"), "500500");
}

TEST(LuaState, APcallInTheScriptCannotSwallowTheBudgetError) {
  LuaState lua({0, "component 'Relentless'", ""});
  lua.setBudget(20ms);
  lua.startStep();
  const std::string message = test_support::messageOf([&] {
    lua.run("while true do\n  pcall(function() while true do end end)\nend", "=relentless");
  });
  EXPECT_EQ(message, "relentless:2: component 'Relentless' ran past its budget of 0.02 s of CPU time");
  EXPECT_EQ(lua.evaluate("1 + 1"), "2");  // usable again once the error reached C++
}

TEST(LuaState, ALoopInACoroutineIsCutToo) {
  LuaState lua({1 << 20, "component 'Co'", ""});
  lua.setBudget(20ms);
  lua.startStep();
  const std::string message = test_support::messageOf([&] {
    lua.run("local co = coroutine.wrap(function()\n  while true do end\nend)\nco()", "=co");
  });
  // coroutine.wrap puts its caller's line in front of the coroutine's error.
  EXPECT_NE(message.find("co:2: component 'Co' ran past its budget of 0.02 s"), std::string::npos) << message;
}

TEST(LuaState, WithoutABudgetLongCodeRunsToItsEnd) {
  LuaState lua;
  lua.startStep();
  lua.run("x = 0 for i = 1, 3e6 do x = x + 1 end");  // far more than one hook period
  EXPECT_EQ(lua.evaluate("x"), "3000000");
}

TEST(LuaState, APendingInterruptEndsAStuckLoopButNotAShortStep) {
  std::atomic<bool> interrupted{false};
  LuaState::watchInterrupt(&interrupted);
  LuaState lua({0, "component 'Stuck'", ""});  // no budget: only the interrupt can end it
  interrupted = true;
  lua.startStep();
  lua.run("x = 0 for i = 1, 1000 do x = x + 1 end");  // a short step finishes: the run ends after it
  EXPECT_EQ(lua.evaluate("x"), "1000");
  lua.startStep();
  const std::string message = test_support::messageOf([&] { lua.run("while true do\nend", "=stuck"); });
  LuaState::watchInterrupt(nullptr);
  EXPECT_EQ(message, "stuck:1: interrupted (Ctrl-C or SIGTERM) while component 'Stuck' ran");
}

TEST(LuaState, FormatsByteCounts) {
  EXPECT_EQ(LuaState::formatBytes(256 * 1024), "256 KiB");
  EXPECT_EQ(LuaState::formatBytes(2 << 20), "2 MiB");
  EXPECT_EQ(LuaState::formatBytes(1000), "1000 bytes");
}

}  // namespace
}  // namespace cobra::script
