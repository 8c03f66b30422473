#pragma once
/// @file
/// A component whose hooks are Lua functions in a script file (like OCL's LuaComponent).

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/script/lua_state.hpp"

namespace cobra::script {

/// Runs the Lua file `script_path`, whose global functions `configureHook`, `startHook`,
/// `updateHook`, `stopHook`, `cleanupHook` and `exceptionHook` (each optional) are its hooks.
/// configureHook and startHook may return false to refuse (nil counts as true).
///
/// In the script, the component is the global `self` (and the global named after it), with
/// everything `exposeComponent` offers plus declarations for the top-level code:
/// @code
/// self:addInputPort("u", "double", "signal u", "1")     -- name, type, doc, unit
/// self:addEventPort("trigger", "Event", "wakes me", "") -- an input whose data triggers update
/// self:addOutputPort("y", "double", "signal y = k u", "1")
/// self:addProperty("k", "double", 2.0, "1", "gain", {min = -10, max = 10})
///                                 -- name, type, initial, unit, doc, optional range (double, int)
/// function updateHook()
///   local fs, u = self.u:read()
///   if fs == "NewData" then self.y:write(self.k * u) end
/// end
/// @endcode
/// Declared ports and properties belong to the component for its whole life; loading the script
/// again (after cleanup) keeps them, with their connections and values, when it declares them
/// with the same types.
///
/// Memory: the Lua state is created when the script is loaded, with a pool of
/// `lua_pool_size` bytes (0 = the system allocator, unbounded), so a Running component's Lua
/// code never calls the system allocator. Exhausting the pool is an error of the hook that ran
/// out: "Lua memory pool of component 'X' exhausted (256 KiB); raise its lua_pool_size
/// property". cleanup (and recover) close the state; the next configure loads the script again.
///
/// Errors: a script that fails to load or run, or a hook raising a Lua error, makes the hook
/// throw cobra::core::Error with Lua's message ("path/file.lua:12: ..."), so the component goes
/// to Exception with it as its last error.
///
/// Budget (LuaState, "Budget and interrupts"): each call of startHook, updateHook, stopHook or
/// exceptionHook may take `lua_budget` s of CPU time; loading the script and configureHook and
/// cleanupHook may take `lua_load_budget` s. Past it the hook is interrupted at the running line
/// and fails like a Lua error ("file.lua:12: component 'X' ran past its budget of 0.01 s of CPU
/// time; raise its lua_budget property"): an endless loop sends the component to Exception
/// instead of stalling its activity (and on the lockstep clock, every component).
class LuaComponent : public core::Component {
 public:
  LuaComponent(std::string name, core::Role role, std::string doc = "component whose hooks are Lua functions");
  ~LuaComponent() override;

  /// Creates the Lua state and runs the script's top level (declaring its ports and
  /// properties), unless already done; configure calls it. Call it earlier to connect the
  /// script's ports before configuring. Not real-time.
  /// @throws cobra::core::Error naming the component and the script (file:line), or telling to
  /// set script_path.
  void loadScript();
  /// The Lua state while the script is loaded, else nullptr (for consoles and tests).
  LuaState* lua() const { return lua_.get(); }

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void stopHook() override;
  void cleanupHook() override;
  void exceptionHook() override;

 private:
  enum Hook { kConfigure, kStart, kUpdate, kStop, kCleanup, kException, kHookCount };
  /// Calls a hook function if the script defines it; its result (false refuses, else true).
  /// @throws cobra::core::Error with Lua's message.
  bool callHook(Hook hook);

  friend struct LuaComponentDeclarations;
  core::Property<std::string> script_path_{"script_path", "", "",
                                           "Lua file defining the hooks (configureHook, updateHook, ...)"};
  core::Property<int> pool_size_{"lua_pool_size", 256 * 1024, "B",
                                 "bytes of the Lua memory pool, reserved when the script loads; 0 = unbounded "
                                 "system allocator (not real-time)"};
  core::Property<double> budget_{"lua_budget", 0.005, "s",
                                 "CPU time one start, update, stop or exception hook may take; past it the hook "
                                 "fails naming the file:line (the component goes to Exception); 0 = none"};
  core::Property<double> load_budget_{"lua_load_budget", 1.0, "s",
                                      "CPU time loading the script, configureHook and cleanupHook may take; 0 = none"};
  /// Gives the Lua state the step budget (`load` false) or the load budget.
  void useBudget(bool load);
  std::unique_ptr<LuaState> lua_;
  std::array<int, kHookCount> hooks_{};
  std::vector<std::unique_ptr<core::PortBase>> own_ports_;
  std::vector<std::unique_ptr<core::PropertyBase>> own_properties_;
};

}  // namespace cobra::script
