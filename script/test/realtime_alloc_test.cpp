// Proves that Lua code running in an activity never calls the system allocator once its pool
// is set up: every malloc-family call of the process (Lua's own, libstdc++'s operator new,
// anything) is counted by replacing malloc for this test executable (glibc supports replacing
// malloc; ours forwards to glibc's __libc_* functions), and operator new is counted separately.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <fstream>
#include <new>

#include <kdl/frames.hpp>
#include <lua.hpp>

#include "cobra/core/core.hpp"
#include "cobra/script/bindings.hpp"
#include "cobra/script/lua_component.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

// Sanitizers own malloc; under them only operator new is counted.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define COBRA_COUNT_MALLOC 0
#else
#define COBRA_COUNT_MALLOC 1
#endif

namespace {
std::atomic<long> g_mallocs{0};
}  // namespace

#if COBRA_COUNT_MALLOC
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);

void* malloc(std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, size);
}
void* memalign(std::size_t alignment, std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  *out = __libc_memalign(alignment, size);
  return *out == nullptr ? ENOMEM : 0;
}
void free(void* p) { __libc_free(p); }
}
#endif


namespace cobra::script {
namespace {

using namespace std::chrono_literals;

struct Counts {
  long mallocs;
  long news;
};

template <class F>
Counts allocationsDuring(F&& body) {
  const long m = g_mallocs.load(), n = cobra::test_support::newCalls();
  body();
  return {g_mallocs.load() - m, cobra::test_support::newCalls() - n};
}

TEST(ScriptRealtimeAlloc, CountersSeeAllocations) {
  static void* volatile escaped = nullptr;
  const Counts c = allocationsDuring([] {
    escaped = std::malloc(10);
    std::free(escaped);
    escaped = new int(3);
    delete static_cast<int*>(escaped);
  });
  EXPECT_GE(c.news, 1);
  if (!COBRA_COUNT_MALLOC) GTEST_SKIP() << "malloc is not counted under a sanitizer";
  EXPECT_GE(c.mallocs, 2);
  // An unbounded state is seen allocating, so a zero below means something.
  LuaState lua;
  const Counts lua_counts = allocationsDuring([&] { lua.run("local t = {} for i = 1, 100 do t[i] = {i} end"); });
  EXPECT_GT(lua_counts.mallocs, 100);
}

TEST(ScriptRealtimeAlloc, LuaFunctionCalledManyTimesInAPoolNeverCallsTheSystem) {
  LuaState lua({512 * 1024, "test state", ""});
  // Creates garbage (tables, strings, closures) on every call, so the collector runs often.
  lua.run(R"(
    total = 0
    function work(i)
      local t = {i, i + 1, name = "step" .. i}
      local f = function(x) return x * 2 end
      total = total + f(t[1]) + #t.name
      return total
    end
  )");
  lua_getglobal(lua.get(), "work");
  const int ref = luaL_ref(lua.get(), LUA_REGISTRYINDEX);
  auto call = [&](int i) {
    lua_rawgeti(lua.get(), LUA_REGISTRYINDEX, ref);
    lua_pushinteger(lua.get(), i);
    lua.call(1, 1);
    lua_pop(lua.get(), 1);
  };
  for (int i = 0; i < 1000; ++i) call(i);  // warm-up: stack and call-info sizes settle
  const Counts c = allocationsDuring([&] {
    for (int i = 0; i < 50000; ++i) call(i);
  });
  EXPECT_EQ(c.mallocs, 0);
  EXPECT_EQ(c.news, 0);
  EXPECT_LE(lua.pool()->peak(), lua.pool()->capacity());
}

TEST(ScriptRealtimeAlloc, RunningLuaComponentOnTheLockstepClockNeverCallsTheSystem) {
  const std::string path = ::cobra::test_support::scratchPath("realtime_alloc_test_worker.lua").string();
  std::ofstream(path) << R"(
self:addInputPort("u", "double", "input", "1")
self:addInputPort("pose", "KDL.Frame", "input pose", "m")
self:addOutputPort("y", "double", "k u", "1")
self:addOutputPort("v", "vector<double>", "samples", "1")
self:addOutputPort("e", "Event", "events", "")
self:addProperty("k", "double", 2.0, "1", "gain")
count = 0
function updateHook()
  local fs, u = self.u:read()
  if fs == "NewData" then self.y:write(self.k * u) end
  local pfs, pose = self.pose:read()
  if pfs ~= "NoData" then self.v:write({pose.p.x, pose.p.y, pose.p.z}) end
  count = count + 1
  if count % 100 == 0 then self.e:write({name = "e_hundred", source = "Worker", stamp = count}) end
end
)";
  LuaComponent worker("Worker", core::Role::Calculation);
  worker.setProperty("script_path", path);
  worker.loadScript();
  core::OutputPort<double> source{"source", "", "1"};
  core::OutputPort<KDL::Frame> poses{"poses", "", "m"};
  core::InputPort<double> sink{"sink", "", "1"};
  core::InputPort<std::vector<double>> samples{"samples", "", "1"};
  core::InputPort<core::Event> events{"events_in", "", ""};
  core::connectPorts(source, worker.port("u"));
  core::connectPorts(poses, worker.port("pose"));
  dynamic_cast<core::OutputPort<std::vector<double>>&>(worker.port("v")).setDataSample(std::vector<double>(3));
  core::connectPorts(worker.port("y"), sink);
  core::connectPorts(worker.port("v"), samples);
  core::connectPorts(worker.port("e"), events, core::ConnPolicy::circular(4));
  core::LockstepClock clock;
  clock.add(worker, 1ms);
  ASSERT_TRUE(worker.configure());
  ASSERT_TRUE(worker.start());

  double y = 0.0;
  std::vector<double> v(3);
  core::Event e;
  auto cycle = [&](int i) {
    source.write(i);
    poses.write(KDL::Frame(KDL::Vector(i, 0, 1)));
    clock.advance(1ms);
    sink.read(y);
    samples.read(v);
    events.read(e);
  };
  for (int i = 0; i < 200; ++i) cycle(i);  // warm-up: port objects and buffers are made once
  const Counts c = allocationsDuring([&] {
    for (int i = 0; i < 20000; ++i) cycle(i);
  });
  EXPECT_EQ(c.mallocs, 0);
  EXPECT_EQ(c.news, 0);
  EXPECT_EQ(worker.state(), core::State::Running) << worker.lastError();
  EXPECT_EQ(y, 2.0 * 19999);
  EXPECT_EQ(v, (std::vector<double>{19999, 0, 1}));
  EXPECT_EQ(e.name, "e_hundred");
  EXPECT_TRUE(worker.stop());
}

}  // namespace
}  // namespace cobra::script
