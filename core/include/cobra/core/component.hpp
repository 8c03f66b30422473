#pragma once
/// @file
/// The component: a named unit with a role, a lifecycle, ports, properties and operations,
/// stepped by an activity (ARCHITECTURE §4).

#include <any>
#include <array>
#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "cobra/core/event.hpp"
#include "cobra/core/operation.hpp"
#include "cobra/core/port.hpp"
#include "cobra/core/property.hpp"

namespace cobra::core {

class Activity;

/// The four roles of the thesis (§2.1). The deployer's linter checks connections against them.
enum class Role { Calculation, Supervision, Decision, Bridge };

/// Lifecycle states (as in OROCOS RTT): PreOperational -configure-> Stopped -start-> Running;
/// stop back to Stopped, cleanup back to PreOperational. A hook that throws moves the component
/// to Exception (recover -> PreOperational); a failure while handling that is FatalError, final.
enum class State { PreOperational, Stopped, Running, Exception, FatalError };

std::string_view toString(Role role);
std::string_view toString(State state);

class Component;

/// Hears a component's lifecycle state changes (Component::addStateListener), so that a watcher
/// (the runner: a component in Exception ends the run) is told instead of polling every state.
/// stateChanged runs on the thread that changed the state: the deployer's for a lifecycle call,
/// the activity's (the real-time path) when a hook throws. It must not block, allocate or throw:
/// note the change (an atomic flag or counter) and let the watcher's own thread act on it.
class StateListener {
 public:
  /// `component` moved from state `from` to `to` (from != to).
  virtual void stateChanged(const Component& component, State from, State to) noexcept = 0;

 protected:
  ~StateListener() = default;
};

/// Outcome of a lifecycle call: ok, or the reason it was refused or failed.
struct [[nodiscard]] Result {
  bool ok = true;
  std::string message;
  explicit operator bool() const { return ok; }
  static Result success() { return {}; }
  static Result failure(std::string why) { return {false, std::move(why)}; }
};

/// Base class of every component. Subclasses declare ports and properties as members, register
/// them in the constructor, and override the hooks they need:
/// @code
/// class Gain : public Component {
///  public:
///   explicit Gain(std::string name) : Component(std::move(name), Role::Calculation, "y = k u") {
///     addPort(in_); addPort(out_); addProperty(k_.range(-10, 10));
///   }
///  protected:
///   void updateHook() override { double u; if (in_.read(u) == FlowStatus::NewData) out_.write(k_() * u); }
///  private:
///   InputPort<double> in_{"in", "signal u", "1"};
///   OutputPort<double> out_{"out", "signal y", "1"};
///   Property<double> k_{"k", 2.0, "1", "gain factor"};
/// };
/// @endcode
/// Lifecycle calls, `setActivity` and by-name access are not real-time and are meant for one
/// controlling thread (the deployer); the hooks run in the component's activity.
class Component {
 public:
  Component(std::string name, Role role, std::string doc);
  virtual ~Component();
  Component(const Component&) = delete;
  Component& operator=(const Component&) = delete;

  const std::string& name() const { return name_; }
  Role role() const { return role_; }
  const std::string& doc() const { return doc_; }
  State state() const { return state_.load(std::memory_order_acquire); }
  bool isRunning() const { return state() == State::Running; }

  // Lifecycle. Each returns what happened; a refused call changes nothing.
  Result configure();  ///< PreOperational or Stopped -> Stopped (configureHook)
  Result start();      ///< Stopped -> Running (startHook), then the activity starts stepping
  Result stop();       ///< Running -> Stopped (activity stops, then stopHook)
  Result cleanup();    ///< Stopped -> PreOperational (cleanupHook)
  Result recover();    ///< Exception -> PreOperational (activity stops, then cleanupHook)

  /// Replaces the activity (default: a SlaveActivity). Refused while Running.
  /// @throws Error naming the component.
  void setActivity(std::unique_ptr<Activity> activity);
  Activity& activity() const { return *activity_; }
  /// Time on the activity's clock: simulated time on the lockstep clock, steady-clock time
  /// otherwise. Real-time safe.
  std::chrono::nanoseconds now() const;

  // Introspection and by-name access.
  const std::vector<PortBase*>& ports() const { return ports_; }
  const std::vector<PropertyBase*>& properties() const { return properties_; }
  std::vector<OperationBase*> operations() const;
  PortBase* findPort(std::string_view name) const;
  PropertyBase* findProperty(std::string_view name) const;
  OperationBase* findOperation(std::string_view name) const;
  /// @throws Error "component 'X' has no port 'y'; its ports are: ...".
  PortBase& port(std::string_view name) const;
  PropertyBase& property(std::string_view name) const;
  OperationBase& operation(std::string_view name) const;

  /// Sets a property by name. The value must have the property's type (an int is accepted for
  /// a double property).
  /// @throws Error naming the component, property, given and expected types; nothing changes.
  template <RegisteredDataType V>
  void setProperty(std::string_view name, const V& value);
  void setProperty(std::string_view name, const char* value) { setProperty(name, std::string(value)); }
  /// Reads a property by name as type V.
  /// @throws Error when there is no such property or V is not its type.
  template <RegisteredDataType V>
  V getProperty(std::string_view name) const;

  /// Calls an operation by name: `comp.call<double>("add", 1.0, 2.0)`.
  /// @throws Error naming the component, the signature and what was wrong.
  template <class R = void, class... A>
  R call(std::string_view name, A&&... arguments);

  /// The `events` output port every component has (logic data: what happened to it).
  OutputPort<Event>& events() { return events_; }
  /// Writes an event named `name` from this component, stamped with `now()`. Real-time safe.
  void emitEvent(std::string_view name) noexcept;
  /// Why the component last failed (a hook's exception or refusal), or "".
  std::string lastError() const;
  /// Number of updateHook calls since construction (cheap introspection).
  std::uint64_t updateCount() const { return update_count_.load(std::memory_order_relaxed); }

  /// At most this many StateListeners per component (fixed slots: announcing allocates nothing).
  static constexpr std::size_t kMaxStateListeners = 4;
  /// Tells `listener` of every later state change of this component (adding it twice does
  /// nothing, also from two threads at once). Any thread, also while Running; not real-time safe.
  /// @throws Error naming the component when its kMaxStateListeners slots are taken.
  void addStateListener(StateListener& listener);
  /// Stops telling `listener`; returns once no call to a listener of this component is under way
  /// on another thread, so the listener may be destroyed then. Also from inside a listener's
  /// stateChanged: it does not wait for the announcement its own thread is making (that call
  /// returns after it; a listener removing itself stays alive until its stateChanged returns),
  /// nor for another thread's made by a thread that waits in removeStateListener from inside a
  /// listener too (they would wait for each other). Not real-time safe (it may wait for a call to end).
  void removeStateListener(StateListener& listener) noexcept;

  /// Runs `change` between two steps of this component: at once when no thread of its
  /// activity is stepping it (or when called from that thread), otherwise the activity thread
  /// runs it before its next update and this call waits for it. Exceptions thrown by `change`
  /// are rethrown here. Not real-time safe; this is how properties, connections and own-thread
  /// operations change a running component without racing its update.
  void runBetweenSteps(const std::function<void()>& change);

 protected:
  /// Return false to refuse configuration (the component stays PreOperational; say why with
  /// `refuse`), or throw for a failure (the component goes to Exception).
  virtual bool configureHook() { return true; }
  /// Return false to refuse starting (the component stays Stopped; say why with `refuse`), or
  /// throw for a failure (the component goes to Exception).
  virtual bool startHook() { return true; }
  /// The periodic or triggered work. Must be real-time safe in production components.
  virtual void updateHook() {}
  virtual void stopHook() {}
  virtual void cleanupHook() {}
  /// Called once when the component enters Exception.
  virtual void exceptionHook() {}

  /// Gives the reason of a refusal: `return refuse("cannot open /dev/ttyS0: permission denied");`
  /// in configureHook or startHook makes configure()/start() fail with "component 'X': <why>"
  /// while the component stays where it was. Always returns false.
  bool refuse(std::string why);

  /// Registers a member port. @throws Error on a duplicate name.
  void addPort(PortBase& port);
  /// Unregisters `port` after removing its connections: for ports made at configure time (their
  /// number depends on a property), from configureHook or cleanupHook. @throws Error when the
  /// component is Running or `port` is not one of its ports.
  void removePort(PortBase& port);
  /// Registers a member input port whose new data triggers updateHook.
  void addEventPort(PortBase& input);
  /// Registers a member property. @throws Error on a duplicate name.
  void addProperty(PropertyBase& property);
  /// Registers an operation from a callable with a fixed signature, e.g. a lambda or
  /// `std::function`. Returns it so arguments can be named: `.arg("x", "m", "target")`.
  template <class R, class... Args>
  OperationBase& addOperation(std::string name, std::function<R(Args...)> function, std::string doc,
                              ExecutionThread thread = ExecutionThread::Own);
  /// Registers a member function: `addOperation("askPlan", &Planner::askPlan, this, "...")`.
  template <class C, class R, class... Args>
  OperationBase& addOperation(std::string name, R (C::*method)(Args...), C* object, std::string doc,
                              ExecutionThread thread = ExecutionThread::Own) {
    return addOperation(std::move(name), std::function<R(Args...)>([object, method](Args... a) -> R {
                          return (object->*method)(std::forward<Args>(a)...);
                        }),
                        std::move(doc), thread);
  }

 private:
  friend class Activity;
  friend class PropertyBase;
  friend class OperationBase;
  friend class PortBase;

  struct PendingChange;
  /// One activity step: apply pending changes, then updateHook when Running.
  void step() noexcept;
  void applyPendingChanges() noexcept;
  /// Moves to Exception after `hook` threw; runs stopHook (if it was running) and exceptionHook.
  void enterException(std::string_view hook, const std::string& what) noexcept;
  void setLastError(std::string message);
  /// Stores the state and tells the listeners when it changed. Real-time safe: no allocation,
  /// no lock (a few atomic operations per listener slot).
  void setState(State to) noexcept;
  /// Calls a hook returning bool; on throw enters Exception. Returns the hook's result.
  bool runHook(std::string_view hook, const std::function<bool()>& body);
  void registerOperation(std::unique_ptr<OperationBase> operation);
  std::string refusal(std::string_view action, std::string_view need) const;
  [[noreturn]] void throwPropertyType(const PropertyBase& property, std::string_view given) const;

  std::string name_;
  Role role_;
  std::string doc_;
  std::atomic<State> state_{State::PreOperational};
  std::array<std::atomic<StateListener*>, kMaxStateListeners> state_listeners_{};
  // Low 16 bits: setState calls telling listeners now (removeStateListener waits for them); above:
  // how many of those are held by threads waiting in removeStateListener from inside a listener.
  std::atomic<int> announcing_{0};
  std::unique_ptr<Activity> activity_;
  OutputPort<Event> events_{"events", "what happened to this component (exceptions, completions)", ""};
  std::vector<PortBase*> ports_;
  std::vector<PropertyBase*> properties_;
  std::vector<std::unique_ptr<OperationBase>> operations_;

  // Changes waiting for the activity thread (see runBetweenSteps). The mutex is only
  // try-locked by the activity thread, so it never blocks there.
  mutable std::recursive_mutex pending_mutex_;
  std::vector<PendingChange*> pending_;
  std::atomic<bool> has_pending_{false};

  mutable std::mutex error_mutex_;
  std::string last_error_;
  std::string refusal_;  // set by refuse() during a hook, consumed by configure()/start()
  std::atomic<std::uint64_t> update_count_{0};
};

template <RegisteredDataType V>
void Component::setProperty(std::string_view name, const V& value) {
  PropertyBase& base = property(name);
  if (auto* typed = dynamic_cast<Property<V>*>(&base)) {
    typed->set(value);
    return;
  }
  if constexpr (std::is_same_v<V, int>) {
    if (auto* as_double = dynamic_cast<Property<double>*>(&base)) {
      as_double->set(static_cast<double>(value));
      return;
    }
  }
  throwPropertyType(base, DataTypeTraits<V>::name);
}

template <RegisteredDataType V>
V Component::getProperty(std::string_view name) const {
  PropertyBase& base = property(name);
  if (auto* typed = dynamic_cast<Property<V>*>(&base)) return typed->value();
  throw Error(base.where() + " is a " + std::string(base.type().name) + ", not a " +
              std::string(DataTypeTraits<V>::name));
}

template <class R, class... A>
R Component::call(std::string_view name, A&&... arguments) {
  OperationBase& op = operation(name);
  std::vector<std::any> packed;
  packed.reserve(sizeof...(A));
  (packed.emplace_back(std::decay_t<A>(std::forward<A>(arguments))), ...);
  std::any result = op.invoke(packed);
  if constexpr (std::is_void_v<R>) {
    return;
  } else {
    if (const R* typed = std::any_cast<R>(&result)) return *typed;
    throw Error(op.where() + " returns " +
                (op.resultType() ? std::string(op.resultType()->name) : std::string("void")) + ", not " +
                std::string(DataTypeTraits<R>::name));
  }
}

template <class R, class... Args>
OperationBase& Component::addOperation(std::string name, std::function<R(Args...)> function, std::string doc,
                                       ExecutionThread thread) {
  auto op = std::make_unique<Operation<R, Args...>>(std::move(name), std::move(function), std::move(doc), thread);
  OperationBase& ref = *op;
  registerOperation(std::move(op));
  return ref;
}

}  // namespace cobra::core
