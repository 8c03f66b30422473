#pragma once
/// @file
/// Fault injection for tests and fault campaigns (cobra faults matrix, cobra soak): make a
/// component's next updateHook throw, as a bug in its code would. The component then goes to
/// Exception exactly as for a real throw (Component::step catches it: lastError, the
/// `e_exception@<name>` event, stopHook and exceptionHook). Nothing else changes: a component no
/// injection names steps as before (one relaxed atomic load per step when none is pending).

#include <string>

namespace cobra::core {

class Component;

/// The next step of `component` that runs its updateHook throws std::runtime_error(`what`) in
/// its place (once; a second injection before it is taken is ignored). Any thread; not on a
/// real-time path (it allocates the text). At most 16 are pending at once: throws beyond.
void injectUpdateException(const Component& component, std::string what);

/// Injections not yet thrown (a component that never steps again keeps its own).
int pendingUpdateExceptions();

}  // namespace cobra::core
