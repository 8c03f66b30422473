#include "cobra/deploy/configurator.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "cobra/deploy/suggest.hpp"
#include "undo_journal.hpp"

namespace cobra::deploy {
namespace {

std::string quoted(const std::string& name) { return "'" + name + "'"; }

std::vector<std::string> namesOf(const core::ComponentRegistry& registry) {
  std::vector<std::string> out;
  for (const core::Component* c : registry.components()) out.push_back(c->name());
  return out;
}

}  // namespace

Configurator::Configurator(ConfiguratorOptions options)
    : options_(std::move(options)),
      packages_(options_.package_path),
      clock_(options_.mode != ClockMode::RealTime ? std::make_unique<core::LockstepClock>() : nullptr) {
  if (clock_) {
    clock_->setBetweenInstants([this] {
      // Every request bumps service_wakeups_ after queueing (ConfiguratorClient::requestSwitch):
      // the count read before servicing covers every request serviceRequests then finds, and a
      // request queued while it runs bumps it again for the next call.
      const std::uint32_t wakeups = service_wakeups_.load(std::memory_order_acquire);
      if (wakeups == hook_serviced_wakeups_) return false;
      hook_serviced_wakeups_ = wakeups;
      return serviceRequests();
    });
  }
}

Configurator::~Configurator() {
  if (service_thread_.joinable()) {
    service_stopping_.store(true);
    wakeService();
    service_thread_.join();
  }
  stopAll();
}

void Configurator::stopAll() noexcept {
  for (auto it = started_.rbegin(); it != started_.rend(); ++it)
    if (core::Component* c = components_.find(*it); c != nullptr && c->isRunning()) (void)c->stop();
  for (core::Component* c : components_.components())
    if (c->isRunning()) (void)c->stop();
}

core::LockstepClock& Configurator::clock() {
  if (!clock_)
    throw core::Error("this Configurator gives each component a thread of its own (ClockMode::RealTime); only "
                      "ClockMode::Simulation and WallClock have a lockstep clock");
  return *clock_;
}

core::Component& Configurator::component(const std::string& name, const SourceLocation& where) const {
  if (core::Component* c = components_.find(name)) return *c;
  throw core::Error(where.text() + ": no component named " + quoted(name) +
                    suggestionText(name, namesOf(components_), "components") +
                    " (components are created from components_list by initConfigurator)");
}

core::Component& Configurator::anyComponent(const std::string& name, const SourceLocation& where) const {
  if (core::Component* c = remote_.find(name)) return *c;
  return component(name, where);
}

bool Configurator::isRemote(std::string_view name) const { return placement_ && remote_.find(name) != nullptr; }

void Configurator::setPlacement(PlacementSpec spec) {
  const std::lock_guard lock(mutex_);
  if (options_.host.empty()) return;
  if (placement_)
    throw core::Error(spec.where.text() + ": a placement is in force already (" + placement_->spec().where.text() +
                      "); declare one placement per application");
  if (!components_.components().empty())
    throw core::Error(spec.where.text() + ": the placement comes after components were created ('" +
                      components_.components().front()->name() +
                      "'); declare it before the first initConfigurator");
  placement_.emplace(std::move(spec), options_.host);
}

core::PortBase& Configurator::port(const std::string& path, const SourceLocation& where) const {
  const PortPath parts = parsePortPath(path, where);
  core::Component& owner = anyComponent(parts.component, where);
  if (core::PortBase* p = owner.findPort(parts.port)) return *p;
  std::vector<std::string> names;
  for (const core::PortBase* p : owner.ports()) names.push_back(p->name());
  throw core::Error(where.text() + ": component " + quoted(owner.name()) + " has no port " + quoted(parts.port) +
                    suggestionText(parts.port, names, "ports of " + owner.name()));
}

void Configurator::initConfigurator(const std::vector<NameEntry>& packages_list,
                                    const std::vector<ComponentSpec>& components_list,
                                    const std::filesystem::path& configuration_folder_path) {
  const std::lock_guard lock(mutex_);
  // Packages first: loading one cannot be undone, but it only makes types available.
  for (const NameEntry& package : packages_list) packages_.load(package.name, package.where);

  detail::UndoJournal journal;
  std::map<std::string, SourceLocation, std::less<>> seen;
  for (const ComponentSpec& spec : components_list) {
    if (spec.peer_name.empty()) throw core::Error(spec.where.text() + ": a component entry needs a peer_name");
    if (const auto it = seen.find(spec.peer_name); it != seen.end())
      throw core::Error(spec.where.text() + ": duplicate instance name " + quoted(spec.peer_name) +
                        ": it is already created at " + it->second.text() + "; give each instance its own peer_name");
    if (components_.find(spec.peer_name) != nullptr || remote_.find(spec.peer_name) != nullptr)
      throw core::Error(spec.where.text() + ": duplicate instance name " + quoted(spec.peer_name) +
                        ": a component of that name already exists; give each instance its own peer_name");
    seen.emplace(spec.peer_name, spec.where);
    (void)packages_.type(spec.component_type, spec.where);  // unknown types fail before anything is created
    if (!options_.host.empty() && !placement_)
      throw core::Error(spec.where.text() + ": this process is host '" + options_.host +
                        "' but no placement says which components live there; declare placement = { hosts = "
                        "{ ... } } before the first initConfigurator (deploy/README.md, Placement)");
    if (placement_) (void)placement_->hostOf(spec.peer_name, spec.where);  // unplaced or doubly placed
  }
  try {
    for (const ComponentSpec& spec : components_list) {
      if (placement_ && placement_->siteOf(spec.peer_name, spec.where) == Placement::Site::Remote) {
        // A shadow: its ports and properties check what the files say of it; nothing of it runs.
        remote_.add(packages_.create(spec.component_type, spec.peer_name, spec.where));
        types_[spec.peer_name] = spec.component_type;
        journal.record("the shadow of remote " + quoted(spec.peer_name), [this, name = spec.peer_name] {
          types_.erase(name);
          remote_.remove(name);
        });
        continue;
      }
      core::Component& created = components_.add(packages_.create(spec.component_type, spec.peer_name, spec.where));
      types_[spec.peer_name] = spec.component_type;
      journal.record("the creation of " + quoted(spec.peer_name), [this, name = spec.peer_name, &created] {
        activities_.erase(name);
        types_.erase(name);
        std::erase_if(clients_, [&](const auto& client) { return client.first == &created; });
        components_.remove(name);
      });
      if (dynamic_cast<ConfiguratorClient*>(&created) != nullptr) attachClient(created);
      // As in RTT, every component starts with an event-driven activity; setActivities replaces
      // it. Given now, before anything is connected, so no running writer can trigger it.
      applyActivity(created, defaultActivity(spec.peer_name, spec.where));
      // One run split over hosts: the local link keeps this process's lockstep clock in step.
      auto* sync = dynamic_cast<core::ClockSync*>(&created);
      if (placement_ && sync != nullptr && clock_sync_ == nullptr) {
        clock_sync_ = sync;
        // On the wall clock nothing meets: the hosts exchange samples as they come.
        if (clock_ && options_.mode == ClockMode::Simulation) clock_->setClockSync(sync);
        journal.record("the clock sync of " + quoted(spec.peer_name), [this] {
          clock_sync_ = nullptr;
          if (clock_) clock_->setClockSync(nullptr);
        });
      }
    }
    if (!configuration_folder_path.empty()) {
      std::vector<ConfigurationSpec> loaded = loadConfigurationFolder(configuration_folder_path);
      std::set<std::string> names;
      for (const ConfigurationSpec& configuration : loaded) {
        if (set_.findConfiguration(configuration.name) != nullptr || !names.insert(configuration.name).second)
          throw core::Error(configuration.where.text() + ": a configuration named " + quoted(configuration.name) +
                            " already exists");
        checkConfiguration(configuration);
      }
      for (ConfigurationSpec& configuration : loaded) set_.addConfiguration(std::move(configuration));
    }
  } catch (const std::exception& e) {
    journal.fail(e.what());
  }
}

void Configurator::configureComponents(const std::vector<NameEntry>& configuration_list) {
  const std::lock_guard lock(mutex_);
  for (const NameEntry& entry : configuration_list) (void)anyComponent(entry.name, entry.where);
  detail::UndoJournal journal;
  for (const NameEntry& entry : configuration_list) {
    if (isRemote(entry.name)) continue;  // its host configures it
    core::Component& c = component(entry.name, entry.where);
    const bool was_preoperational = c.state() == core::State::PreOperational;
    if (const core::Result result = c.configure(); !result) {
      const std::string note = detail::recoverAfterFailure(c);
      journal.fail(entry.where.text() + ": cannot configure " + quoted(c.name()) + ": " + result.message + note);
    }
    if (was_preoperational)
      journal.record("the configuration of " + quoted(c.name()), [&c] {
        if (const core::Result r = c.cleanup(); !r) throw core::Error(r.message);
      });
  }
}

void Configurator::startComponents(const std::vector<NameEntry>& start_list) {
  const std::lock_guard lock(mutex_);
  for (const NameEntry& entry : start_list) (void)anyComponent(entry.name, entry.where);
  detail::UndoJournal journal;
  // Components added to the registry by others (scripts) may have no activity from us yet:
  // give them the default one before any component of the list starts.
  for (const NameEntry& entry : start_list) {
    if (isRemote(entry.name)) continue;  // its host starts it
    core::Component& c = component(entry.name, entry.where);
    if (c.isRunning() || activities_.count(c.name()) != 0) continue;
    try {
      applyActivity(c, defaultActivity(c.name(), entry.where));
    } catch (const std::exception& e) {
      journal.fail(entry.where.text() + ": cannot give " + quoted(c.name()) + " an activity: " + e.what());
    }
    journal.record("the default activity of " + quoted(c.name()), [this, &c] { removeActivity(c); });
  }
  for (const NameEntry& entry : start_list) {
    if (isRemote(entry.name)) continue;
    core::Component& c = component(entry.name, entry.where);
    if (c.isRunning()) continue;  // starting twice is harmless, as in RTT's deployer scripts
    if (const core::Result result = c.start(); !result) {
      const std::string note = detail::recoverAfterFailure(c, true);  // it was Stopped before
      journal.fail(entry.where.text() + ": cannot start " + quoted(c.name()) + ": " + result.message + note);
    }
    started_.push_back(c.name());
    journal.record("the start of " + quoted(c.name()), [this, &c] {
      std::erase(started_, c.name());
      if (const core::Result r = c.stop(); !r) throw core::Error(r.message);
    });
  }
}

void Configurator::stopComponents(const std::vector<NameEntry>& stop_list) {
  const std::lock_guard lock(mutex_);
  for (const NameEntry& entry : stop_list) (void)anyComponent(entry.name, entry.where);
  detail::UndoJournal journal;
  for (const NameEntry& entry : stop_list) {
    if (isRemote(entry.name)) continue;  // its host stops it
    core::Component& c = component(entry.name, entry.where);
    if (!c.isRunning()) continue;
    if (const core::Result result = c.stop(); !result)
      journal.fail(entry.where.text() + ": cannot stop " + quoted(c.name()) + ": " + result.message +
                   detail::recoverAfterFailure(c));
    std::erase(started_, c.name());
    journal.record("the stop of " + quoted(c.name()), [this, &c] {
      if (const core::Result r = c.start(); !r) throw core::Error(r.message);
      started_.push_back(c.name());
    });
  }
}

void Configurator::cleanupComponents(const std::vector<NameEntry>& cleanup_list) {
  const std::lock_guard lock(mutex_);
  for (const NameEntry& entry : cleanup_list) (void)anyComponent(entry.name, entry.where);
  detail::UndoJournal journal;
  for (const NameEntry& entry : cleanup_list) {
    if (isRemote(entry.name)) continue;  // its host cleans it up
    core::Component& c = component(entry.name, entry.where);
    if (c.state() == core::State::PreOperational) continue;
    if (const core::Result result = c.cleanup(); !result)
      journal.fail(entry.where.text() + ": cannot clean up " + quoted(c.name()) + ": " + result.message +
                   detail::recoverAfterFailure(c));
    journal.record("the cleanup of " + quoted(c.name()), [&c] {
      if (const core::Result r = c.configure(); !r) throw core::Error(r.message);
    });
  }
}

void Configurator::addPeers(const std::vector<PeerSpec>& peers_list) {
  const std::lock_guard lock(mutex_);
  auto updated = peers_;  // applied all at once below, so a bad entry changes nothing
  for (const PeerSpec& spec : peers_list) {
    (void)anyComponent(spec.peer_name, spec.where);
    if (isRemote(spec.peer_name)) {  // its host adds them (and checks them against its own placement)
      for (const std::string& peer : spec.peers_to_add) (void)anyComponent(peer, spec.where);
      continue;
    }
    auto& peers = updated[spec.peer_name];
    for (const std::string& peer : spec.peers_to_add) {
      (void)anyComponent(peer, spec.where);
      if (isRemote(peer))
        throw core::Error(spec.where.text() + ": " + quoted(peer) + " (host '" + placement_->hostOf(peer, spec.where) +
                          "') cannot be a peer of " + quoted(spec.peer_name) + " (host '" + placement_->host() +
                          "'): operations do not cross hosts; place both on one host, or exchange events through ports");
      if (peer == spec.peer_name)
        throw core::Error(spec.where.text() + ": " + quoted(peer) + " cannot be a peer of itself");
      if (std::find(peers.begin(), peers.end(), peer) == peers.end()) peers.push_back(peer);
    }
  }
  peers_ = std::move(updated);
}

std::string Configurator::componentTypeOf(const std::string& component) const {
  const auto it = types_.find(component);
  return it == types_.end() ? std::string() : it->second;
}

const ActivitySpec* Configurator::activityOf(const std::string& component) const {
  const auto it = activities_.find(component);
  return it == activities_.end() ? nullptr : &it->second;
}

const std::vector<std::string>& Configurator::peersOf(const std::string& name) const {
  static const std::vector<std::string> none;
  const auto it = peers_.find(name);
  return it == peers_.end() ? none : it->second;
}

ActivitySpec Configurator::defaultActivity(const std::string& name, const SourceLocation& where) const {
  return ActivitySpec{name, 0.0, 0, "ORO_SCHED_OTHER", where};
}

ActivitySpec Configurator::checkActivity(const ActivitySpec& spec, bool running_ok) const {
  core::Component& c = component(spec.peer_name, spec.where);
  const std::string head = spec.where.text() + ": activity of " + quoted(c.name()) + ": ";
  if (!running_ok && c.isRunning()) throw core::Error(head + "it is Running; stop it before changing its activity");
  if (c.state() == core::State::Exception || c.state() == core::State::FatalError)
    throw core::Error(head + "it is " + std::string(core::toString(c.state())) + " (" + c.lastError() +
                      "); recover it first");
  if (!std::isfinite(spec.period) || spec.period < 0.0)
    throw core::Error(head + "period must be a number of seconds >= 0 (0 = event-driven), got " +
                      std::to_string(spec.period));
  if (spec.period > 0.0 && spec.period < 1e-9)
    throw core::Error(head + "period " + std::to_string(spec.period) + " s is below 1 ns");
  if (spec.period > 1e9) throw core::Error(head + "period " + std::to_string(spec.period) + " s is too long");
  if (!std::isfinite(spec.max_age) || spec.max_age < 0.0)
    throw core::Error(head + "max_age must be a number of seconds > 0 (the oldest its hand-over may get), got " +
                      std::to_string(spec.max_age));
  if (spec.max_age > 0.0 && !spec.own_pace)
    throw core::Error(head + "max_age bounds the hand-over of a component at its own pace; add own_pace = true "
                      "or leave max_age out (this one steps in the executor's schedule)");
  ActivitySpec checked = spec;
  if (toScheduler(spec.scheduler, spec.where) == core::Scheduler::Fifo) {
    if (spec.priority > 99 || spec.priority < 0)
      throw core::Error(head + "priority " + std::to_string(spec.priority) + " is outside 1..99 for " + spec.scheduler);
    if (spec.priority == 0) checked.priority = 1;
  }
  return checked;
}

void Configurator::applyActivity(core::Component& c, const ActivitySpec& spec) {
  const auto period = std::chrono::nanoseconds(std::llround(spec.period * 1e9));
  if (clock_) clock_->remove(c);
  if (clock_ && !(spec.own_pace && options_.mode == ClockMode::WallClock)) {
    clock_->add(c, period);
    activities_[c.name()] = spec;
    return;
  }
  const core::Scheduler scheduler = toScheduler(spec.scheduler, spec.where);
  std::unique_ptr<core::Activity> activity;
  if (period.count() > 0) activity = std::make_unique<core::PeriodicActivity>(period, spec.priority, scheduler);
  else activity = std::make_unique<core::EventActivity>(spec.priority, scheduler);
  replaceActivity(c, std::move(activity));
  activities_[c.name()] = spec;
  if (handover_watcher_ != nullptr && spec.own_pace && options_.mode == ClockMode::WallClock)
    handover_watcher_->watchHandover(c, std::chrono::nanoseconds(std::llround(spec.handoverBound() * 1e9)));
}

void Configurator::removeActivity(core::Component& c) {
  activities_.erase(c.name());
  if (clock_) clock_->remove(c);
  replaceActivity(c, std::make_unique<core::SlaveActivity>());
}

void Configurator::replaceActivity(core::Component& c, std::unique_ptr<core::Activity> activity) {
  // A write on a connection into one of c's event ports triggers c's activity from the writer's
  // thread; replacing the activity under it would race. So the connections whose writer runs
  // on a thread are removed while the activity changes, and made again (empty) after.
  struct Detached {
    core::PortBase* output;
    core::PortBase* input;
    core::ConnPolicy policy;
  };
  std::vector<Detached> detached;
  for (core::PortBase* input : c.ports()) {
    if (!input->isEventPort()) continue;
    for (const auto& channel : input->connections()) {
      const core::Component* writer = channel->writer().owner();
      if (writer != nullptr && writer != &c && writer->activity().hasRunningThread())
        detached.push_back({&channel->writer(), input, channel->policy()});
    }
  }
  for (const Detached& d : detached) core::disconnectPorts(*d.output, *d.input);
  std::exception_ptr error;
  try {
    c.setActivity(std::move(activity));
  } catch (...) {
    error = std::current_exception();
  }
  for (const Detached& d : detached) core::connectPorts(*d.output, *d.input, d.policy);
  if (error) std::rethrow_exception(error);
}

void Configurator::setActivities(const std::vector<ActivitySpec>& activities_list) {
  const std::lock_guard lock(mutex_);
  std::vector<ActivitySpec> checked;
  std::map<std::string, SourceLocation, std::less<>> seen;
  for (const ActivitySpec& spec : activities_list) {
    if (const auto it = seen.find(spec.peer_name); it != seen.end())
      throw core::Error(spec.where.text() + ": " + quoted(spec.peer_name) + " already has an activity in this list (" +
                        it->second.text() + "); give each component one");
    seen.emplace(spec.peer_name, spec.where);
    if (isRemote(spec.peer_name)) continue;  // its host runs it
    checked.push_back(checkActivity(spec, false));
  }
  detail::UndoJournal journal;
  for (const ActivitySpec& spec : checked) {
    const auto asked = std::find_if(activities_list.begin(), activities_list.end(),
                                    [&](const ActivitySpec& a) { return a.peer_name == spec.peer_name; });
    if (spec.priority != asked->priority)
      warnings_.push_back(spec.where.text() + ": activity of '" + spec.peer_name + "': priority " +
                          std::to_string(asked->priority) + " is not a real-time priority; using " +
                          std::to_string(spec.priority));
    core::Component& c = component(spec.peer_name, spec.where);
    const auto previous = activities_.find(spec.peer_name);
    std::optional<ActivitySpec> before;
    if (previous != activities_.end()) before = previous->second;
    try {
      applyActivity(c, spec);
    } catch (const std::exception& e) {
      journal.fail(spec.where.text() + ": cannot set the activity of " + quoted(c.name()) + ": " + e.what());
    }
    journal.record("the activity of " + quoted(c.name()), [this, &c, before] {
      if (before) applyActivity(c, *before);
      else removeActivity(c);
    });
  }
}

}  // namespace cobra::deploy
