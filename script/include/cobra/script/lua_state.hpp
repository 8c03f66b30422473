#pragma once
/// @file
/// RAII owner of a Lua 5.4 state, optionally bounded by a PoolAllocator, with error handling
/// that turns every Lua failure into a `cobra::core::Error` (never a crash or a panic).

#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

#include "cobra/script/pool_allocator.hpp"

struct lua_State;
struct lua_Debug;

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
///
/// **Budget and interrupts.** Lua code can loop forever; a component's step must not. Every
/// state (and every coroutine it makes) has a count hook called each `kHookInstructions` Lua
/// instructions. With a budget set (`setBudget`), the hook measures the CPU time of the calling
/// thread since the step began (`startStep`; from the hook's first call in the step, so to within
/// `kHookInstructions` instructions; CPU time, so a loaded machine's preemptions do not count)
/// and, past the budget, raises a Lua error "file.lua:12: <owner> ran past its budget of
/// <s> s of CPU time; <hint>" at the running line; from then on it raises at every instruction
/// until the error reaches C++ (`popError`), so a `pcall` in the script cannot swallow it. When
/// the flag given to `watchInterrupt` is set (Ctrl-C, SIGTERM), the hook raises "interrupted" in any
/// step that has run `kInterruptGrace` of CPU time, so a script stuck in a loop cannot keep the
/// process alive, while steps that end by themselves are left to finish. Cost: with a count hook
/// set, Lua's interpreter checks the count at every instruction (a tight arithmetic loop pays
/// most, chart callbacks that mostly call C++ little: bench/statechart_bench, LuaNoHook against
/// LuaHookNoBudget and LuaHookBudget); the hook itself runs every `kHookInstructions`
/// instructions and reads the clock only in a step that long; nothing allocates until the error
/// is raised. C functions called by Lua are not interrupted (the hook runs between Lua
/// instructions).
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
  /// Pops a failed call's error object from `thread` (this state's main thread when nullptr; a
  /// coroutine's own stack holds its error) and gives the message to report (pool exhaustion is
  /// recognised from `status`, a lua_pcall or lua_resume status).
  std::string popError(int status, lua_State* thread = nullptr);
  /// "256 KiB", "1 MiB", "1000 bytes".
  static std::string formatBytes(std::size_t bytes);

  /// Lua instructions between two calls of the budget's hook.
  static constexpr int kHookInstructions = 10000;
  /// CPU time a step may still run once an interrupt is pending (it ends by itself, or is cut).
  static constexpr std::chrono::milliseconds kInterruptGrace{100};

  /// CPU time each step may take from now on (0 = no limit); `hint` ends the message, e.g.
  /// "raise its lua_budget property". Not real-time.
  void setBudget(std::chrono::nanoseconds budget, std::string hint = {});
  std::chrono::nanoseconds budget() const noexcept { return budget_; }
  /// A step begins: its CPU time counts from here (to the hook's granularity). Real-time safe.
  void startStep() noexcept;
  /// The flag the hook watches in every state of the process (e.g. set by a SIGINT/SIGTERM
  /// handler); nullptr: none. The flag must outlive the states.
  static void watchInterrupt(const std::atomic<bool>* flag) noexcept;

 private:
  static void countHook(lua_State* L, lua_Debug* ar);
  /// True when the step started by startStep has used more than `limit` of CPU time; the first
  /// hook call of a step only notes the time.
  bool stepLongerThan(std::chrono::nanoseconds limit) noexcept;

  LuaMemory memory_;
  std::unique_ptr<PoolAllocator> pool_;
  lua_State* state_ = nullptr;
  std::chrono::nanoseconds budget_{0};
  std::string budget_message_;   // "ran past its budget of 0.01 s of CPU time; hint"
  std::chrono::nanoseconds step_start_{0};
  bool step_timed_ = false;      // step_start_ was read in this step
  std::string interrupt_message_;  // "interrupted (Ctrl-C or SIGTERM) while <owner> ran"
  // The message the hook raised in this step (it now runs every instruction), or nullptr.
  const char* trip_reason_ = nullptr;
};

}  // namespace cobra::script
