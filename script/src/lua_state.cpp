#include "cobra/script/lua_state.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

#include <lua.hpp>

#include "cobra/core/error.hpp"

namespace cobra::script {

namespace {

// Every Lua call cobra makes is protected, so a panic means a bug in cobra: report it loudly.
int panic(lua_State* L) {
  const char* message = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "(error object is not a string)";
  auto* self = *static_cast<LuaState**>(lua_getextraspace(L));
  std::fprintf(stderr, "[cobra] unprotected Lua error in %s: %s\n", self ? self->memory().owner.c_str() : "?", message);
  std::abort();
}

// The flag watched by every state's hook (watchInterrupt).
std::atomic<const std::atomic<bool>*> g_interrupt{nullptr};

std::chrono::nanoseconds threadCpuTime() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
}

int openLibraries(lua_State* L) {
  luaL_openlibs(L);
  return 0;
}

}  // namespace

std::string LuaState::formatBytes(std::size_t bytes) {
  if (bytes >= (1u << 20) && bytes % (1u << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  if (bytes >= 1024 && bytes % 1024 == 0) return std::to_string(bytes >> 10) + " KiB";
  return std::to_string(bytes) + " bytes";
}

LuaState::LuaState(LuaMemory memory) : memory_(std::move(memory)) {
  if (memory_.pool_bytes > 0) {
    pool_ = std::make_unique<PoolAllocator>(memory_.pool_bytes);
    state_ = lua_newstate(&PoolAllocator::luaAlloc, pool_.get());
  } else {
    state_ = luaL_newstate();
  }
  const std::string hint = memory_.hint.empty() ? std::string() : "; " + memory_.hint;
  if (state_ == nullptr)
    throw core::Error("Lua memory pool of " + memory_.owner + " (" + formatBytes(memory_.pool_bytes) +
                      ") is too small to create a Lua state" + hint);
  *static_cast<LuaState**>(lua_getextraspace(state_)) = this;
  lua_atpanic(state_, &panic);
  lua_pushcfunction(state_, &openLibraries);
  const int status = lua_pcall(state_, 0, 0, 0);
  if (status != LUA_OK) {
    std::string why = popError(status);
    lua_close(state_);
    state_ = nullptr;
    throw core::Error(why + " while opening the Lua standard libraries");
  }
  interrupt_message_ = "interrupted (Ctrl-C or SIGTERM) while " + memory_.owner + " ran";
  lua_sethook(state_, &countHook, LUA_MASKCOUNT, kHookInstructions);  // coroutines inherit it
}

void LuaState::watchInterrupt(const std::atomic<bool>* flag) noexcept { g_interrupt.store(flag); }

void LuaState::setBudget(std::chrono::nanoseconds budget, std::string hint) {
  budget_ = budget.count() > 0 ? budget : std::chrono::nanoseconds(0);
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%g", std::chrono::duration<double>(budget_).count());
  budget_message_ = memory_.owner + " ran past its budget of " + seconds + " s of CPU time" +
                    (hint.empty() ? std::string() : "; " + hint);
}

void LuaState::startStep() noexcept {
  step_timed_ = false;
  if (trip_reason_ != nullptr) {
    trip_reason_ = nullptr;
    lua_sethook(state_, &countHook, LUA_MASKCOUNT, kHookInstructions);
  }
}

bool LuaState::stepLongerThan(std::chrono::nanoseconds limit) noexcept {
  const auto now = threadCpuTime();
  if (!step_timed_) {
    step_timed_ = true;
    step_start_ = now;
    return false;
  }
  return now - step_start_ > limit;
}

void LuaState::countHook(lua_State* L, lua_Debug* ar) {
  LuaState* self = from(L);
  if (self == nullptr) return;
  const char* why = self->trip_reason_;
  if (why == nullptr) {
    const std::atomic<bool>* flag = g_interrupt.load(std::memory_order_relaxed);
    const bool interrupted = flag != nullptr && flag->load(std::memory_order_relaxed);
    if (self->budget_.count() == 0 && !interrupted) return;
    if (self->budget_.count() > 0 && self->stepLongerThan(self->budget_)) why = self->budget_message_.c_str();
    else if (interrupted && self->stepLongerThan(kInterruptGrace)) why = self->interrupt_message_.c_str();
    if (why == nullptr) return;
    self->trip_reason_ = why;
  }
  // From now on every instruction raises (the running thread and the main one), so a pcall in
  // the script that catches this error cannot keep the loop going; popError (the error reached
  // C++) and startStep undo it.
  lua_sethook(L, &countHook, LUA_MASKCOUNT, 1);
  if (L != self->state_) lua_sethook(self->state_, &countHook, LUA_MASKCOUNT, 1);
  lua_getinfo(L, "Sl", ar);
  lua_pushfstring(L, "%s:%d: %s", ar->short_src, ar->currentline, why);
  lua_error(L);
}

LuaState* LuaState::from(lua_State* L) {
  // Threads (coroutines) start with a copy of the main thread's extra space.
  return *static_cast<LuaState**>(lua_getextraspace(L));
}

LuaState::~LuaState() {
  if (state_ != nullptr) lua_close(state_);
}

std::string LuaState::popError(int status, lua_State* thread) {
  lua_State* L = thread != nullptr ? thread : state_;
  // The error reached C++: a budget or interrupt error has done its work, the state is usable
  // again (a console may evaluate in it). The step's CPU time still counts.
  if (trip_reason_ != nullptr) {
    trip_reason_ = nullptr;
    lua_sethook(state_, &countHook, LUA_MASKCOUNT, kHookInstructions);
  }
  std::string message;
  if (status == LUA_ERRMEM) {
    if (pool_)
      message = "Lua memory pool of " + memory_.owner + " exhausted (" + formatBytes(memory_.pool_bytes) + ")" +
                (memory_.hint.empty() ? std::string() : "; " + memory_.hint);
    else
      message = memory_.owner + " ran out of memory";
  } else if (lua_type(L, -1) == LUA_TSTRING) {
    message = lua_tostring(L, -1);
  } else {
    message = std::string("Lua error with a ") + luaL_typename(L, -1) + " value as error object";
  }
  lua_pop(L, 1);
  return message;
}

void LuaState::call(int arguments, int results, std::string_view context) {
  const int status = lua_pcall(state_, arguments, results, 0);
  if (status == LUA_OK) return;
  std::string message = popError(status);
  throw core::Error(context.empty() ? message : std::string(context) + ": " + message);
}

void LuaState::run(std::string_view code, const std::string& chunk_name) {
  const int status = luaL_loadbufferx(state_, code.data(), code.size(), chunk_name.c_str(), "t");
  if (status != LUA_OK) throw core::Error(popError(status));
  call(0, 0);
}

void LuaState::runFile(const std::string& path) {
  const int status = luaL_loadfilex(state_, path.c_str(), "t");
  if (status != LUA_OK) throw core::Error(popError(status));
  call(0, 0);
}

std::string LuaState::evaluate(std::string_view expression) {
  const std::string code = "return tostring(" + std::string(expression) + ")";
  const int status = luaL_loadbufferx(state_, code.data(), code.size(), "=evaluate", "t");
  if (status != LUA_OK) throw core::Error(popError(status));
  call(0, 1);
  std::string value = lua_type(state_, -1) == LUA_TSTRING ? lua_tostring(state_, -1) : "";
  lua_pop(state_, 1);
  return value;
}

}  // namespace cobra::script
