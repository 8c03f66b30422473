#pragma once
// What a run's actions and faults name, checked against the loaded deployment before the run
// starts (internal to cobra::run_core): a misspelled chart, state path, component, operation,
// port or property, or a value its property or port cannot take, is one line with the file:line
// of the entry, what it names and what there is, instead of a fault that never fires or fails
// only when it fires.

#include <vector>

#include "cobra/core/introspection.hpp"
#include "cobra/run/run_spec.hpp"
#include "session.hpp"

struct lua_State;

namespace cobra::run {

/// @throws std::runtime_error "FILE:LINE: what is wrong; did you mean ..." for the first problem.
/// `L` holds the entry's table (ActionSpec::lua_ref) with the value a `set` or `write` plays.
void checkAction(const ActionSpec& action, const core::ComponentRegistry& refs, const std::vector<Chart>& charts,
                 lua_State* L);

}  // namespace cobra::run
