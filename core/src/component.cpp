#include "cobra/core/component.hpp"

#include <algorithm>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <vector>
#include <thread>
#include <utility>

#include "cobra/core/activity.hpp"
#include "cobra/core/fault_injection.hpp"

namespace cobra::core {

namespace {

// Injected update exceptions (fault_injection.hpp): few, rare, set off the real-time path, held
// in a fixed table of slots without a lock, so that a component's step never waits for another
// thread: the count is read by every step; the slots are scanned only when it is not zero. A slot
// is Free, Writing (an injection fills it), Armed (its target may take it) or Taking (its target
// or the target's destructor empties it); only the thread that moved it out of Armed touches its
// text.
constexpr std::size_t kInjectionSlots = 16;
enum SlotState : int { kFree, kWriting, kArmed, kTaking };
struct InjectionSlot {
  std::atomic<int> state{kFree};
  std::atomic<const Component*> target{nullptr};  // read before the state decides: atomic
  std::string what;
};
std::atomic<int> g_injected{0};
InjectionSlot g_injections[kInjectionSlots];

// Empties the Armed slot of `component`, if any, into `what`; true when there was one.
bool takeInjection(const Component* component, std::string* what) {
  for (InjectionSlot& slot : g_injections) {
    int armed = kArmed;
    if (slot.state.load(std::memory_order_acquire) != kArmed || slot.target.load(std::memory_order_relaxed) != component)
      continue;
    if (!slot.state.compare_exchange_strong(armed, kTaking, std::memory_order_acquire)) continue;
    if (what != nullptr) *what = std::move(slot.what);
    slot.what.clear();
    slot.target.store(nullptr, std::memory_order_relaxed);
    slot.state.store(kFree, std::memory_order_release);
    g_injected.fetch_sub(1, std::memory_order_relaxed);
    return true;
  }
  return false;
}

// Throws the injection of `component` when there is one (removing it).
void throwIfInjected(const Component* component) {
  std::string what;
  if (takeInjection(component, &what)) throw std::runtime_error(what);
}

}  // namespace

void injectUpdateException(const Component& component, std::string what) {
  // One pending injection per component: a fault replayed every period while the component is
  // not stepping (stopped, in Exception) would otherwise fill the table.
  for (InjectionSlot& slot : g_injections)
    if (slot.state.load(std::memory_order_acquire) == kArmed && slot.target.load(std::memory_order_relaxed) == &component)
      return;
  for (InjectionSlot& slot : g_injections) {
    int free = kFree;
    if (!slot.state.compare_exchange_strong(free, kWriting, std::memory_order_acquire)) continue;
    slot.target.store(&component, std::memory_order_relaxed);
    slot.what = std::move(what);
    g_injected.fetch_add(1, std::memory_order_relaxed);
    slot.state.store(kArmed, std::memory_order_release);
    return;
  }
  throw std::runtime_error("fault injection: " + std::to_string(kInjectionSlots) +
                           " update exceptions are pending already (components that do not step take none): "
                           "inject into running components");
}

int pendingUpdateExceptions() { return g_injected.load(std::memory_order_relaxed); }

/// A change queued for the activity thread; lives on the waiting caller's stack, so the
/// activity thread neither allocates nor frees anything to run it.
struct Component::PendingChange {
  const std::function<void()>* change;
  std::exception_ptr error;
  std::atomic<bool> done{false};
};

std::string_view toString(Role role) {
  switch (role) {
    case Role::Calculation: return "Calculation";
    case Role::Supervision: return "Supervision";
    case Role::Decision: return "Decision";
    case Role::Bridge: return "Bridge";
  }
  return "?";
}

std::string_view toString(State state) {
  switch (state) {
    case State::PreOperational: return "PreOperational";
    case State::Stopped: return "Stopped";
    case State::Running: return "Running";
    case State::Exception: return "Exception";
    case State::FatalError: return "FatalError";
  }
  return "?";
}

Component::Component(std::string name, Role role, std::string doc)
    : name_(std::move(name)), role_(role), doc_(std::move(doc)), activity_(std::make_unique<SlaveActivity>()) {
  if (name_.empty()) throw Error("a component needs a non-empty name");
  if (name_.find_first_of(". \t\n") != std::string::npos)
    throw Error("component name '" + name_ + "' may not contain '.' or spaces (it is used in paths like Name.port)");
  activity_->component_ = this;
  pending_.reserve(16);
  addPort(events_);
}

Component::~Component() {
  // An injection it never threw dies with it (another component may get its address).
  while (g_injected.load(std::memory_order_relaxed) != 0 && takeInjection(this, nullptr)) {
  }
  // By now the subclass's members are gone; an update running on another thread would touch
  // freed memory. Stop components before destroying them (ComponentRegistry does).
  if (state() == State::Running && activity_->hasRunningThread())
    std::fprintf(stderr, "[cobra] warning: component '%s' destroyed while Running on a thread; stop it first\n",
                 name_.c_str());
  if (activity_->hasRunningThread() && !activity_->isActivityThread()) activity_->stopStepping();
  // Now, while every member is alive: events_ outlives pending_mutex_, which disconnecting locks.
  events_.disconnect();
}

namespace {
constexpr std::string_view kFatalAdvice = "a component in FatalError cannot be used again; remove it and create a new one";
}  // namespace

std::string Component::refusal(std::string_view action, std::string_view need) const {
  return "component '" + name_ + "': cannot " + std::string(action) + ": it is " + std::string(toString(state())) +
         (need.empty() ? "" : "; " + std::string(need));
}

void Component::setLastError(std::string message) {
  std::lock_guard lock(error_mutex_);
  last_error_ = std::move(message);
}

std::string Component::lastError() const {
  std::lock_guard lock(error_mutex_);
  return last_error_;
}

bool Component::runHook(std::string_view hook, const std::function<bool()>& body) {
  // A change that runBetweenSteps applies at once (no activity thread) holds this lock too, so
  // it never overlaps a lifecycle hook.
  std::lock_guard lock(pending_mutex_);
  try {
    return body();
  } catch (const std::exception& e) {
    enterException(hook, e.what());
  } catch (...) {
    enterException(hook, "unknown exception");
  }
  return false;
}

Result Component::configure() {
  const State s = state();
  if (s != State::PreOperational && s != State::Stopped)
    return Result::failure(refusal("configure", s == State::Running   ? "stop it first" :
                                                s == State::Exception ? "recover it first" :
                                                                        kFatalAdvice));
  if (!runHook("configureHook", [this] { return configureHook(); })) {
    if (state() == State::Exception || state() == State::FatalError) return Result::failure(lastError());
    setLastError("component '" + name_ + "': " +
                 (refusal_.empty() ? std::string("configureHook refused the configuration") : std::exchange(refusal_, {})));
    return Result::failure(lastError());
  }
  setState(State::Stopped);
  return Result::success();
}

Result Component::start() {
  const State s = state();
  if (s != State::Stopped)
    return Result::failure(refusal("start", s == State::PreOperational ? "configure it first" :
                                            s == State::Running           ? "it is already running" :
                                            s == State::Exception         ? "recover and configure it first" :
                                                                             kFatalAdvice));
  // Held until the activity thread runs: runBetweenSteps sees "no thread" only under this lock,
  // so a change it applies at once cannot overlap the first steps.
  std::lock_guard lock(pending_mutex_);
  if (!runHook("startHook", [this] { return startHook(); })) {
    if (state() == State::Exception || state() == State::FatalError) return Result::failure(lastError());
    setLastError("component '" + name_ + "': " +
                 (refusal_.empty() ? std::string("startHook refused to start") : std::exchange(refusal_, {})));
    return Result::failure(lastError());
  }
  setState(State::Running);
  activity_->startStepping();
  return Result::success();
}

Result Component::stop() {
  if (state() != State::Running) return Result::failure(refusal("stop", "only a Running component can stop"));
  if (activity_->isActivityThread() && !activity_->stoppableFromOwnThread())
    return Result::failure("component '" + name_ + "': cannot stop from its own activity thread; throw from "
                           "updateHook to enter Exception, or stop it from the deployer");
  activity_->stopStepping();
  // The activity thread may have moved the component to Exception while we joined it.
  if (state() != State::Running) return Result::failure(lastError());
  setState(State::Stopped);
  runHook("stopHook", [this] {
    stopHook();
    return true;
  });
  if (state() != State::Stopped) return Result::failure(lastError());
  return Result::success();
}

Result Component::cleanup() {
  if (state() != State::Stopped) return Result::failure(refusal("clean up", "stop it first"));
  runHook("cleanupHook", [this] {
    cleanupHook();
    return true;
  });
  if (state() != State::Stopped) return Result::failure(lastError());
  setState(State::PreOperational);
  return Result::success();
}

Result Component::recover() {
  if (state() != State::Exception) return Result::failure(refusal("recover", "only a component in Exception can recover"));
  if (activity_->isActivityThread() && !activity_->stoppableFromOwnThread())
    return Result::failure("component '" + name_ + "': cannot recover from its own activity thread");
  activity_->stopStepping();
  std::lock_guard lock(pending_mutex_);  // see runHook
  try {
    cleanupHook();
  } catch (const std::exception& e) {
    setLastError("component '" + name_ + "': cleanupHook threw during recover: " + e.what());
    setState(State::FatalError);
    emitEvent("e_fatal_error@" + name_);
    return Result::failure(lastError());
  } catch (...) {
    setLastError("component '" + name_ + "': cleanupHook threw during recover");
    setState(State::FatalError);
    emitEvent("e_fatal_error@" + name_);
    return Result::failure(lastError());
  }
  setState(State::PreOperational);
  return Result::success();
}

void Component::enterException(std::string_view hook, const std::string& what) noexcept {
  try {
    const bool was_running = state() == State::Running;
    setLastError("component '" + name_ + "': " + std::string(hook) + " threw: " + what);
    std::fprintf(stderr, "[cobra] %s; component is now in Exception\n", lastError().c_str());
    setState(State::Exception);
    emitEvent("e_exception@" + name_);
    std::string_view handler = "stopHook";
    try {
      if (was_running && hook != "stopHook") stopHook();
      handler = "exceptionHook";
      exceptionHook();
    } catch (const std::exception& e) {
      setLastError("component '" + name_ + "': " + std::string(handler) + " threw while handling an exception (" +
                   lastError() + "): " + e.what());
      setState(State::FatalError);
      emitEvent("e_fatal_error@" + name_);
    } catch (...) {
      setLastError("component '" + name_ + "': " + std::string(handler) + " threw while handling an exception (" +
                   lastError() + "): unknown exception");
      setState(State::FatalError);
      emitEvent("e_fatal_error@" + name_);
    }
  } catch (...) {
    // Out of memory while building a message: the state must still change.
    setState(State::FatalError);
  }
}

namespace {

// One addStateListener or removeStateListener at a time, of any component: two threads adding one
// listener cannot both find it absent and take two slots. Rare calls, never on a real-time path.
std::mutex g_listeners_mutex;

// Component::announcing_: the announcements under way in its low bits, above them those of them
// held by threads waiting in removeStateListener from inside a listener.
constexpr int kAnnouncement = 1, kWaitingInside = 1 << 16;
int underWay(int announcing) noexcept { return announcing & (kWaitingInside - 1); }
int waitingInside(int announcing) noexcept { return announcing / kWaitingInside; }

// The components whose state change the calling thread is announcing now, outermost first (a
// listener may change another component's state): removeStateListener, called from inside a
// listener, does not wait for its own thread's announcements. Constant-initialised, so it needs
// no TLS guard and no allocation. Levels beyond kKept are counted, not kept (see announcedHere).
struct Announcing {
  static constexpr int kKept = 8;
  std::array<const Component*, kKept> components{};
  int depth = 0;
};
thread_local Announcing t_announcing;

// How many of `component`'s announcements the calling thread is inside. A level beyond the kKept
// outermost (its component unknown) counts as `component`'s: a removal from there may return
// before another thread's call ends, but never waits for its own thread forever.
int announcedHere(const Component* component) noexcept {
  int mine = std::max(0, t_announcing.depth - Announcing::kKept);
  for (int i = 0; i < std::min(t_announcing.depth, Announcing::kKept); ++i)
    if (t_announcing.components[static_cast<std::size_t>(i)] == component) ++mine;
  return mine;
}

}  // namespace

void Component::setState(State to) noexcept {
  const State from = state_.exchange(to, std::memory_order_acq_rel);
  if (from == to) return;
  // Counted before the slots are read: removeStateListener clears a slot, then waits while a
  // count is held (by another thread), so a listener it returned from is never called again
  // (both sequentially consistent: either this sees the cleared slot, or the remover sees the count).
  announcing_.fetch_add(kAnnouncement);
  if (t_announcing.depth < Announcing::kKept) t_announcing.components[static_cast<std::size_t>(t_announcing.depth)] = this;
  ++t_announcing.depth;
  for (std::atomic<StateListener*>& slot : state_listeners_)
    if (StateListener* listener = slot.load()) listener->stateChanged(*this, from, to);
  --t_announcing.depth;
  announcing_.fetch_sub(kAnnouncement);
}

void Component::addStateListener(StateListener& listener) {
  std::lock_guard lock(g_listeners_mutex);
  for (const std::atomic<StateListener*>& slot : state_listeners_)
    if (slot.load() == &listener) return;
  for (std::atomic<StateListener*>& slot : state_listeners_) {
    if (slot.load() != nullptr) continue;
    slot.store(&listener);
    return;
  }
  throw Error("component '" + name_ + "': already " + std::to_string(kMaxStateListeners) +
              " state listeners (Component::kMaxStateListeners); remove one first");
}

void Component::removeStateListener(StateListener& listener) noexcept {
  {
    std::lock_guard lock(g_listeners_mutex);
    for (std::atomic<StateListener*>& slot : state_listeners_)
      if (slot.load() == &listener) slot.store(nullptr);
  }
  // The calling thread's own announcements of this component (a listener removing itself or
  // another) end after this returns: waiting for them would never end. Nor are those of another
  // thread waiting here from inside a listener waited for: two such threads would wait for each
  // other forever (then one may return while the other's listener call is still under way).
  const int mine = announcedHere(this);
  announcing_.fetch_add(mine * kWaitingInside);
  for (int now = announcing_.load(); underWay(now) > waitingInside(now); now = announcing_.load())
    std::this_thread::yield();
  announcing_.fetch_sub(mine * kWaitingInside);
}

bool Component::refuse(std::string why) {
  refusal_ = std::move(why);
  return false;
}

void Component::emitEvent(std::string_view name) noexcept {
  Event event;
  event.name = name;
  event.source = std::string_view(name_);
  event.stamp = now();
  events_.write(event);
}

std::chrono::nanoseconds Component::now() const { return activity_->now(); }

void Component::setActivity(std::unique_ptr<Activity> activity) {
  if (!activity) throw Error("component '" + name_ + "': setActivity needs an activity, got none");
  if (state() == State::Running || activity_->hasRunningThread())
    throw Error("component '" + name_ + "': cannot change the activity while it is " + std::string(toString(state())) +
                "; stop it first");
  if (activity->component_ != nullptr && activity->component_ != this)
    throw Error("component '" + name_ + "': this activity already belongs to component '" +
                activity->component_->name() + "'");
  activity->component_ = this;
  activity_ = std::move(activity);
}

void Component::step() noexcept {
  if (has_pending_.load(std::memory_order_acquire)) applyPendingChanges();
  if (state() != State::Running) return;
  try {
    if (g_injected.load(std::memory_order_relaxed) != 0) [[unlikely]] throwIfInjected(this);
    updateHook();
    // Only the stepping thread writes it: a plain increment, not a locked read-modify-write.
    update_count_.store(update_count_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  } catch (const std::exception& e) {
    enterException("updateHook", e.what());
  } catch (...) {
    enterException("updateHook", "unknown exception");
  }
}

void Component::applyPendingChanges() noexcept {
  std::unique_lock lock(pending_mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;  // a caller is queueing; take it on the next step
  for (PendingChange* pending : pending_) {
    try {
      (*pending->change)();
    } catch (...) {
      pending->error = std::current_exception();
    }
    // The caller polls `done` and may destroy `pending` as soon as it is set: touch nothing after.
    pending->done.store(true, std::memory_order_release);
  }
  pending_.clear();  // keeps capacity: no deallocation here
  has_pending_.store(false, std::memory_order_release);
}

void Component::runBetweenSteps(const std::function<void()>& change) {
  PendingChange pending{&change, nullptr, {}};
  {
    std::lock_guard lock(pending_mutex_);
    // Decided under the lock: start() starts the thread while holding it, and the lifecycle
    // hooks run holding it, so a change applied here overlaps neither a step nor a hook.
    if (!activity_->hasRunningThread() || activity_->isActivityThread()) {
      change();
      return;
    }
    pending_.push_back(&pending);
    has_pending_.store(true, std::memory_order_release);
  }
  activity_->trigger();
  // The activity thread may stop before taking the change (stop() races with us); then the
  // change runs here, since nothing steps the component any more.
  while (!pending.done.load(std::memory_order_acquire)) {
    if (!activity_->hasRunningThread()) {
      std::lock_guard lock(pending_mutex_);
      auto it = std::find(pending_.begin(), pending_.end(), &pending);
      // Checked again under the lock: start() may have restarted the thread meanwhile; then
      // that thread takes the change.
      if (it != pending_.end() && !activity_->hasRunningThread()) {
        pending_.erase(it);
        change();
        return;
      }
    }
    std::this_thread::sleep_for(std::chrono::microseconds(50));
  }
  if (pending.error) std::rethrow_exception(pending.error);
}

void Component::addPort(PortBase& port) {
  if (findPort(port.name()) != nullptr)
    throw Error("component '" + name_ + "' already has a port named '" + port.name() + "'");
  if (port.owner_ != nullptr && port.owner_ != this)
    throw Error("port '" + port.name() + "' already belongs to component '" + port.owner_->name() + "'");
  port.owner_ = this;
  ports_.push_back(&port);
}

void Component::removePort(PortBase& port) {
  if (isRunning()) throw Error("component '" + name_ + "' is Running: stop it before removing port '" + port.name() + "'");
  const auto found = std::find(ports_.begin(), ports_.end(), &port);
  if (found == ports_.end()) throw Error("component '" + name_ + "' has no port '" + port.name() + "' to remove");
  port.disconnect();
  ports_.erase(found);
  port.owner_ = nullptr;
  port.event_port_ = false;
}

void Component::addEventPort(PortBase& input) {
  if (input.direction() != PortDirection::Input)
    throw Error("component '" + name_ + "': port '" + input.name() + "' is an output; only inputs can be event ports");
  addPort(input);
  input.event_port_ = true;
}

void Component::addProperty(PropertyBase& property) {
  if (findProperty(property.name()) != nullptr)
    throw Error("component '" + name_ + "' already has a property named '" + property.name() + "'");
  property.owner_ = this;
  properties_.push_back(&property);
}

void Component::registerOperation(std::unique_ptr<OperationBase> operation) {
  if (findOperation(operation->name()) != nullptr)
    throw Error("component '" + name_ + "' already has an operation named '" + operation->name() + "'");
  operation->owner_ = this;
  operations_.push_back(std::move(operation));
}

std::vector<OperationBase*> Component::operations() const {
  std::vector<OperationBase*> out;
  for (const auto& op : operations_) out.push_back(op.get());
  return out;
}

namespace {
template <class List>
std::string namesOf(const List& list) {
  std::string names;
  for (const auto& item : list) names += (names.empty() ? "" : ", ") + item->name();
  return names.empty() ? "(none)" : names;
}
}  // namespace

PortBase* Component::findPort(std::string_view name) const {
  for (PortBase* p : ports_)
    if (p->name() == name) return p;
  return nullptr;
}
PropertyBase* Component::findProperty(std::string_view name) const {
  for (PropertyBase* p : properties_)
    if (p->name() == name) return p;
  return nullptr;
}
OperationBase* Component::findOperation(std::string_view name) const {
  for (const auto& op : operations_)
    if (op->name() == name) return op.get();
  return nullptr;
}

PortBase& Component::port(std::string_view name) const {
  if (PortBase* p = findPort(name)) return *p;
  throw Error("component '" + name_ + "' has no port '" + std::string(name) + "'; its ports are: " + namesOf(ports_));
}
PropertyBase& Component::property(std::string_view name) const {
  if (PropertyBase* p = findProperty(name)) return *p;
  throw Error("component '" + name_ + "' has no property '" + std::string(name) +
              "'; its properties are: " + namesOf(properties_));
}
OperationBase& Component::operation(std::string_view name) const {
  if (OperationBase* op = findOperation(name)) return *op;
  throw Error("component '" + name_ + "' has no operation '" + std::string(name) +
              "'; its operations are: " + namesOf(operations_));
}

void Component::throwPropertyType(const PropertyBase& property, std::string_view given) const {
  throw Error(property.where() + " is a " + std::string(property.type().name) + ": cannot set it from a " +
              std::string(given) + "; expected " + std::string(property.type().format));
}

}  // namespace cobra::core
