#pragma once
/// @file
/// Runs Lua deployment files against a Configurator: the thesis' Configurator API (§3.2.2) as
/// Lua functions taking Lua tables, e.g.
/// @code
/// packages_list = { "cobra_signal" }
/// components_list = { { peer_name = "Sine", component_type = "SineGenerator" }, ... }
/// initConfigurator(packages_list, components_list, "configurations")
/// setActivities({ { peer_name = "Sine", period = 0.001, priority = 95, scheduler = rtt.globals.ORO_SCHED_RT } })
/// connectPorts({ { output = "Sine.out", input = "Gain.in", conn_policy = cp } })
/// configureComponents({ "Sine", "Gain" })
/// startComponents({ "Sine", "Gain" })
/// getReferences()        -- then Sine.frequency = 2, Gain:getState(), ...
/// @endcode
/// plus `stopComponents`, `cleanupComponents`, `defineDeployment(name, {components=, activities=,
/// connections=, scope=})` (`scope`: the switch group, e.g. one per robot; see DeploymentSpec),
/// `defineConfiguration(name, { Component = { property = value } })` (a named configuration in
/// the file itself, values as in Lua configuration files: lua_configuration.hpp),
/// `applyDeployment(name)`, `applyConfiguration(name)`, and the RTT shims
/// `rtt.globals.ORO_SCHED_RT` / `ORO_SCHED_OTHER` and `rtt.Variable("ConnPolicy")` (a data
/// policy table whose `type` and `size` can be set).
/// The global `COBRA_CHARTS` is the folder of cobra's reusable supervisor charts, ending in "/"
/// (`DepSup.fsm_path = COBRA_CHARTS .. "deployment_supervisor.lua"`), when cobra's data folder
/// is found (install_layout.hpp: an installed tool, cobra's own build tree, or COBRA_DATA_DIR).
///
/// One host of an application split over hosts (ConfiguratorOptions::host): the global `host` is
/// its name (nil otherwise), and the global table `placement` (placement.hpp) is put in force at
/// the first `initConfigurator`; its entries' lines are found in the first file run.
///
/// The configuration folder of `initConfigurator` may hold configurations as Lua tables
/// (`name.lua`, see lua_configuration.hpp) as well as `name.cfg` files.
///
/// Every table entry is given the file:line where it is written, so Configurator errors name it.
/// Lua does not keep the lines of table entries, so they are found in the source text: the call
/// `startComponents(start_list)` is looked up on its line, the definition `start_list = {` is
/// searched from there, and each entry is the next line at or after the previous entry that
/// contains its identifying strings (its quoted name, or its `output` and `input` paths). When
/// that fails (a list built by code), the entry gets the line of the call.

#include <memory>
#include <string>

#include "cobra/deploy/configurator.hpp"
#include "cobra/script/lua_state.hpp"

namespace cobra::deploy {

/// Binds one Configurator into one LuaState (both must outlive the LuaDeployer).
class LuaDeployer {
 public:
  LuaDeployer(Configurator& configurator, script::LuaState& lua);
  ~LuaDeployer();
  LuaDeployer(const LuaDeployer&) = delete;
  LuaDeployer& operator=(const LuaDeployer&) = delete;

  /// Runs a deployment file. @throws core::Error "file:line: ..." from Lua or the Configurator;
  /// the Configurator has undone the failing call (see its rollback contract).
  void runFile(const std::string& path);
  /// Runs Lua source given in a string (`chunk_name` appears in errors).
  void run(const std::string& code, const std::string& chunk_name);

  Configurator& configurator() { return configurator_; }

  struct Impl;  ///< what the Lua functions reach through their upvalue (opaque)

 private:
  Configurator& configurator_;
  script::LuaState& lua_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cobra::deploy
