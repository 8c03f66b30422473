#include "cobra/core/property.hpp"

#include "cobra/core/activity.hpp"
#include "cobra/core/component.hpp"

namespace cobra::core {

std::string PropertyBase::where() const {
  return (owner_ ? "component '" + owner_->name() + "': " : std::string()) + "property '" + name_ + "'";
}

void PropertyBase::applyChange(const std::function<void()>& change) {
  if (owner_ != nullptr) owner_->runBetweenSteps(change);
  else change();
}

void PropertyBase::readLocked(const std::function<void()>& read) const {
  // The owner's activity thread is the only one that writes values while it runs, so it reads
  // without the lock (a hook must never wait for a thread that is queueing a change).
  if (owner_ == nullptr || owner_->activity().isActivityThread()) {
    read();
    return;
  }
  std::lock_guard lock(owner_->pending_mutex_);
  read();
}

void PropertyBase::throwReadOnly() const {
  throw Error(where() + " is read-only; it reports a value and cannot be set");
}

}  // namespace cobra::core
