#pragma once
// Internal: the undo list that makes every Configurator call all-or-nothing, and the recovery
// of a component whose hook failed during such a call.

#include <exception>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/core/error.hpp"

namespace cobra::deploy::detail {

/// Records how to undo each change a call makes; on failure, `fail` undoes them newest first
/// and throws the error with a note on what was undone.
class UndoJournal {
 public:
  /// `what` describes the change for the error note when undoing it fails.
  void record(std::string what, std::function<void()> undo) { steps_.push_back({std::move(what), std::move(undo)}); }
  std::size_t size() const { return steps_.size(); }

  /// Undoes every recorded change, newest first, and throws `error` followed by what was undone.
  /// An undo step that throws is reported in the message, and the others still run.
  [[noreturn]] void fail(const std::string& error) noexcept(false) {
    std::string failures;
    for (auto it = steps_.rbegin(); it != steps_.rend(); ++it) {
      try {
        it->undo();
      } catch (const std::exception& e) {
        failures += "; could not undo " + it->what + ": " + e.what();
      }
    }
    const std::string note = steps_.empty()      ? "; nothing was changed"
                             : steps_.size() == 1 ? "; the change made before it was undone"
                                                  : "; the " + std::to_string(steps_.size()) +
                                                        " changes made before it were undone";
    steps_.clear();
    throw core::Error(error + note + failures);
  }

 private:
  struct Step {
    std::string what;
    std::function<void()> undo;
  };
  std::vector<Step> steps_;
};

/// Takes a component whose hook threw during a call out of Exception: recovers it (to
/// PreOperational) and, when it was Stopped before the call (`reconfigure`), configures it
/// again, so that nothing is left in Exception and undoing the call leaves it as it was.
/// Returns a note for the error message ("" when it was not in Exception).
inline std::string recoverAfterFailure(core::Component& c, bool reconfigure = false) {
  if (c.state() != core::State::Exception) return "";
  if (!c.recover()) return " (" + c.name() + " could not be recovered: " + c.lastError() + ")";
  if (!reconfigure) return " (" + c.name() + " was recovered to PreOperational)";
  if (c.configure()) return " (" + c.name() + " was recovered and configured again)";
  return " (" + c.name() + " was recovered but could not be configured again: " + c.lastError() + ")";
}

}  // namespace cobra::deploy::detail
