#pragma once
/// @file
/// Lua access to components, as the thesis' Configurator `getReferences()` gives it (§3.2.2).
///
/// A component exposed as `Comp` offers, in Lua:
/// - `Comp.prop` reads a property (converted as in convert.hpp; types without a conversion as
///   text) and `Comp.prop = v` sets it (checked by the core: type, range, read-only; the Lua
///   error carries the core's message);
/// - `Comp.port` a port object: `:name()`, `:type()`, `:unit()`, `:doc()`, `:connected()`,
///   `:read()` (returns the flow status "NoData"/"OldData"/"NewData" and the value, nil on
///   NoData, as rttlua does; an output port is read through a private data connection made at
///   the first read, which sees what is written after it) and `:write(v)` (output ports);
/// - `Comp:op(a, b)` (or `Comp.op(a, b)`) calls an operation, arguments converted to its
///   argument types; returns its result (nothing for void operations);
/// - `Comp:configure()`, `:start()`, `:stop()`, `:cleanup()`, `:recover()` return true or raise
///   the lifecycle call's message; `:getState()`, `:getName()`, `:getRole()`, `:getLastError()`;
/// - `Comp:now()` (s, on its activity's clock: simulated on the lockstep clock) and
///   `Comp:emitEvent("e_done")` (on its `events` port; real-time safe), as rttlua's helpers;
/// - `Comp()` and `tostring(Comp)` give the console description (`toText(describe(c))`).
/// These method names win over elements of the same name (reach those with the C++ API).
/// An unknown name raises an error listing the component's ports, properties and operations.
/// Every error raised has the Lua caller's file:line in front.
///
/// Real-time: reading a property or port of a built-in scalar type, and writing a port of any
/// built-in type (once its buffer has the data's size) allocates nothing from the system; tables
/// and strings come from the Lua state's allocator (its pool when bounded). Operation calls,
/// property sets and lifecycle calls allocate.
///
/// Lifetime: an exposed component must outlive every use of it from the Lua state.

#include <string>

#include "cobra/core/component.hpp"
#include "cobra/core/introspection.hpp"
#include "cobra/script/lua_state.hpp"

namespace cobra::script {

/// Sets the global named after `component` to its Lua object.
/// @throws cobra::core::Error when the Lua state runs out of memory.
void exposeComponent(LuaState& lua, core::Component& component);
/// Same, under the global `global` (e.g. "self"). One component has one Lua object per state.
void exposeComponent(LuaState& lua, core::Component& component, const std::string& global);

/// Exposes every component of `registry` under its name, and defines the Lua function
/// `getReferences()` that does it again (for components added since).
void getReferences(LuaState& lua, core::ComponentRegistry& registry);

}  // namespace cobra::script
