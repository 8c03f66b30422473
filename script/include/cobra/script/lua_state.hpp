#pragma once
/// @file
/// RAII owner of a Lua 5.4 state, optionally bounded by a PoolAllocator, with error handling
/// that turns every Lua failure into a `cobra::core::Error` (never a crash or a panic).

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

#include "cobra/script/pool_allocator.hpp"

struct lua_State;

namespace cobra::script {

/// How a LuaState gets its memory.
struct LuaMemory {
  /// Arena size in bytes; 0 = unbounded (the system allocator, for consoles and tools).
  std::size_t pool_bytes = 0;
  /// Who owns the state, for messages: "component 'Supervisor'".
  std::string owner = "Lua state";
  /// What to do when the pool is exhausted: "raise its lua_pool_size property".
  std::string hint;
};

/// A Lua state with the standard libraries open. Not thread-safe: use it from one thread at a
/// time. Errors raised by Lua code are reported with the chunk name and line Lua gives
/// ("path/to/script.lua:12: ..."); pool exhaustion is reported as "Lua memory pool of <owner>
/// exhausted (<size>); <hint>".
class LuaState {
 public:
  /// @throws cobra::core::Error when the state cannot be created (e.g. a pool too small for the
  /// standard libraries; the message gives the size needed).
  explicit LuaState(LuaMemory memory = {});
  ~LuaState();
  LuaState(const LuaState&) = delete;
  LuaState& operator=(const LuaState&) = delete;

  lua_State* get() const { return state_; }
  /// The LuaState owning `L` (any thread or coroutine of it), or nullptr for a foreign state.
  static LuaState* from(lua_State* L);
  const LuaMemory& memory() const { return memory_; }
  /// The pool, or nullptr for an unbounded state.
  const PoolAllocator* pool() const { return pool_.get(); }

  /// Runs Lua source; `chunk_name` appears in error messages ("=console", "@file.lua").
  /// @throws cobra::core::Error with Lua's message (file:line) when it fails to load or run.
  void run(std::string_view code, const std::string& chunk_name = "=(string)");
  /// Loads and runs a file. @throws cobra::core::Error naming the file (and line).
  void runFile(const std::string& path);
  /// Runs `code` as an expression and gives its value with Lua's `tostring` (for consoles and
  /// tests). @throws like `run`.
  std::string evaluate(std::string_view expression);

  /// Calls the function below its `arguments` on the Lua stack in protected mode (like
  /// lua_pcall with `results` results) and throws on failure, with `context` in front of Lua's
  /// message. Real-time safe when it succeeds and the function allocates nothing outside the
  /// pool.
  void call(int arguments, int results, std::string_view context = {});
  /// Pops a failed call's error object and gives the message to report (pool exhaustion is
  /// recognised from `status`, a lua_pcall status).
  std::string popError(int status);
  /// "256 KiB", "1 MiB", "1000 bytes".
  static std::string formatBytes(std::size_t bytes);

 private:
  LuaMemory memory_;
  std::unique_ptr<PoolAllocator> pool_;
  lua_State* state_ = nullptr;
};

}  // namespace cobra::script
