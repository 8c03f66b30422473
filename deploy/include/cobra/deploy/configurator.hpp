#pragma once
/// @file
/// The Configurator (thesis §3.2.2): deploys components from tables — packages, instances,
/// activities, connections, peers, lifecycle — and switches between named deployments and
/// configurations at run time.
///
/// Every call is all-or-nothing: it checks its whole list first, then applies it, and when an
/// entry still fails while applying, everything that call did is undone (components it created
/// are destroyed, connections it made are removed, components it configured are cleaned up,
/// components it started are stopped) before the error is thrown. The error starts with the
/// file:line of the failing entry and names the component, port or property and what to do.
/// Nothing half-deployed keeps running.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "cobra/core/introspection.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/deploy/configurator_client.hpp"
#include "cobra/deploy/deployment_set.hpp"
#include "cobra/deploy/lint.hpp"
#include "cobra/core/realtime_executor.hpp"
#include "cobra/deploy/package_registry.hpp"
#include "cobra/deploy/placement.hpp"
#include "cobra/deploy/spec.hpp"

namespace cobra::deploy {

namespace detail {
class UndoJournal;
}

/// How activities run.
enum class ClockMode {
  /// Every component is stepped by one LockstepClock owned by the Configurator, with the period
  /// of its activity (0: when triggered); priority and scheduler are checked but not used.
  /// Time advances only through `clock().advance(...)`, so runs are deterministic.
  Simulation,
  /// Every component gets its own thread: PeriodicActivity for a period > 0, EventActivity for 0.
  RealTime,
  /// The wall clock as a real robot runs: every component is on the lockstep clock, as in
  /// Simulation, and a core::RealtimeExecutor (the run's) steps that clock's schedule every
  /// period on one real-time thread, so a run makes the lockstep run's decisions up to timing.
  /// Components whose activity says `own_pace` get a thread of their own instead (spec.hpp). No
  /// ClockSync is met: hosts exchange samples as they come.
  WallClock,
};

struct ConfiguratorOptions {
  ClockMode mode = ClockMode::Simulation;
  /// true: connections that break the role rules (lint.hpp) are refused; false: they are made
  /// and the violations are returned (and kept in `warnings()`).
  bool strict_roles = false;
  /// Directories searched for shared-library packages, before COBRA_PACKAGE_PATH.
  std::vector<std::filesystem::path> package_path;
  /// This process's host in the application's placement (placement.hpp); "" = no placement:
  /// every component runs in this process, and a placement given to setPlacement is ignored.
  std::string host;
};

/// Owns the packages, the components, the lockstep clock (in simulation) and the peer table of
/// one deployment. Its public operations are serialised by a mutex, so the deployer's thread and
/// the service thread (see ConfiguratorClient) may both use it; on the lockstep clock, call it
/// between two `clock().advance(...)`, which is when its changes take effect. Components that
/// are ConfiguratorClients (supervisors) ask for switches from their steps; the Configurator
/// carries them out between steps and answers them.
class Configurator {
 public:
  explicit Configurator(ConfiguratorOptions options = {});
  /// Stops every running component (last started first), then destroys them.
  ~Configurator();
  Configurator(const Configurator&) = delete;
  Configurator& operator=(const Configurator&) = delete;

  /// Puts `spec` in force when the options name a host (ignored otherwise): from then on each
  /// component created is local, remote or everywhere (Placement::Site). A remote component is
  /// created as a shadow that is never configured, started or stepped: its ports and properties
  /// are known, so names and types are still checked, and what is set on it is ignored. Call it
  /// before the first initConfigurator.
  /// @throws core::Error for a bad placement (Placement's constructor), when components exist
  ///         already, or when a placement is in force already.
  void setPlacement(PlacementSpec spec);
  /// The placement in force, or nullptr (no host, or no placement given yet).
  const Placement* placement() const { return placement_ ? &*placement_ : nullptr; }
  /// True when `component` is on another host (never without a placement).
  bool isRemote(std::string_view component) const;
  /// The shadows of the remote components (empty without a placement).
  const core::ComponentRegistry& remoteComponents() const { return remote_; }
  core::ComponentRegistry& remoteComponents() { return remote_; }
  /// The topics of the connections between hosts this process makes: its writer ends (output
  /// ports of its components read on other hosts) and reader ends, "Component/port" each, in the
  /// order made.
  const std::vector<std::string>& writerTopics() const { return writer_topics_; }
  const std::vector<std::string>& readerTopics() const { return reader_topics_; }
  /// The link of a run split over hosts: the first local component implementing core::ClockSync
  /// (the DDS link) once a placement is in force, set on the lockstep clock when it is created
  /// (in ClockMode::RealTime nothing meets it; its lostPeers() still tell of lost peers).
  /// nullptr otherwise.
  core::ClockSync* clockSync() const { return clock_sync_; }

  /// Loads the packages, creates the component instances, and reads every configuration file
  /// (`*.cfg`, see loadConfigurationFile) of `configuration_folder_path` (none when empty),
  /// checking each value against the new components. May be called again to add more.
  /// @throws core::Error "file:line: ..." for an unknown package or type (closest names given),
  ///         a duplicate instance name, or a bad configuration; then no component was added
  ///         (packages loaded before the error stay loaded: loading only adds types).
  void initConfigurator(const std::vector<NameEntry>& packages_list, const std::vector<ComponentSpec>& components_list,
                        const std::filesystem::path& configuration_folder_path = {});

  /// Configures the listed components in order (PreOperational or Stopped -> Stopped).
  /// @throws core::Error naming the failing entry; components this call configured are cleaned up.
  void configureComponents(const std::vector<NameEntry>& configuration_list);
  /// Starts the listed components in order. Components get an event-driven activity (period 0)
  /// when created, as in RTT; `setActivities` replaces it.
  /// @throws core::Error naming the failing entry; components this call started are stopped.
  void startComponents(const std::vector<NameEntry>& start_list);
  /// Stops the listed components in order (Running -> Stopped). Not in the thesis' list; the
  /// deployment switch and scripts need it.
  void stopComponents(const std::vector<NameEntry>& stop_list);
  /// Cleans up the listed components in order (Stopped -> PreOperational).
  void cleanupComponents(const std::vector<NameEntry>& cleanup_list);

  /// Adds peers: a component knows its peers by name (a supervisor calls their operations).
  /// Under a placement, the entries of remote components are left to their host, and a local
  /// component cannot have a remote peer (operations do not cross hosts).
  /// @throws core::Error naming the entry when a component or peer does not exist, or when a
  ///         local component is given a remote peer (naming both and their hosts).
  void addPeers(const std::vector<PeerSpec>& peers_list);
  /// The peers of `component`, in the order added (empty when it has none).
  const std::vector<std::string>& peersOf(const std::string& component) const;
  /// The component type `component` was created from ("" for one this configurator did not make).
  std::string componentTypeOf(const std::string& component) const;
  /// The activity last set for `component`, or nullptr.
  const ActivitySpec* activityOf(const std::string& component) const;

  /// Sets each listed component's activity (see ClockMode). Periods are in s; 0 is event-driven.
  /// Priority 0 with a real-time scheduler is raised to 1 (with a warning), as RTT does.
  /// @throws core::Error naming the entry for an unknown component, a Running component (stop
  ///         it first), a negative period, an unknown scheduler or a priority above 99.
  void setActivities(const std::vector<ActivitySpec>& activities_list);

  /// How the real-time executor runs this deployment on the wall clock (spec.hpp, ExecutorSpec),
  /// in every clock mode (the files are the same); makes the component `Executor` whose events
  /// port carries the executor's events (executorMonitor()).
  /// @throws core::Error "file:line: setExecutor: ..." for a priority outside 1..99, an unknown
  ///         scheduler, a CPU this machine does not have, an unknown on_deadline_miss, a negative
  ///         safe_stop_after or period, or a second setExecutor.
  void setExecutor(ExecutorSpec spec);
  const ExecutorSpec& executorSpec() const { return executor_; }
  /// The executor's options for the activities now in force: the tick is the spec's period or
  /// else the greatest common divisor of the periodic components' periods (1 ms when none).
  /// @throws core::Error "file:line: setExecutor: period ... is not a divisor of the period ...
  ///         of 'X' (its activity at file:line)".
  core::ExecutorOptions executorOptions() const;
  /// The component `Executor` (nullptr before setExecutor).
  core::Component* executorMonitor() const { return executor_monitor_; }
  /// Has `executor` watch the hand-over age of every component at its own pace on the wall clock
  /// (spec.hpp: max_age), now and as later switches give components their own pace. Call before
  /// the executor starts; nullptr (before the executor is destroyed) ends it.
  void watchHandovers(core::RealtimeExecutor* executor);

  /// Connects each `output` port to its `input` port with its policy, after checking all of
  /// them: ports exist, output -> input direction, same type, not already connected, and the
  /// role rules (lint.hpp). Under a placement (placement.hpp): local -> local as above; a local
  /// output read by a remote input gets one writer end on the placement's transport (topic
  /// "Component/port", however many remote inputs read it); a remote output read by a local
  /// input gets a reader end on that topic; remote -> remote, and a connection between an
  /// `everywhere` component and a remote one (its host makes it with its own instance), make
  /// nothing here. The connection's type and size are kept, the placement's QoS added.
  /// @return the role violations (made anyway unless `strict_roles`).
  /// @throws core::Error "file:line: cannot connect ...", or the violations when strict.
  std::vector<LintViolation> connectPorts(const std::vector<ConnectionSpec>& connections_list);
  /// The connections connectPorts made that are still there, in the order made (those a
  /// deployment made are its own: DeploymentSpec::connections). Connections components make
  /// themselves (a Reporter to its peers' ports) are not the Configurator's and are not listed.
  std::vector<ConnectionSpec> madeConnections() const;

  /// The components, by name: what the script layer turns into references (`TrajGen.max_vel`).
  core::ComponentRegistry& getReferences() { return components_; }
  const core::ComponentRegistry& getReferences() const { return components_; }

  /// Named deployments and configurations; `initConfigurator` adds the configuration files.
  DeploymentSet& deploymentSet() { return set_; }
  const DeploymentSet& deploymentSet() const { return set_; }

  /// Switches to deployment `name`: components of the previous deployment that `name` does not
  /// run are stopped, its connections that `name` does not have are removed, activities are
  /// set (a Running component whose activity changes is stopped and restarted), the new
  /// connections are made, and the components of `name` are configured if needed and started,
  /// in their listed order. Everything is checked before anything changes; if applying still
  /// fails, the previous deployment is restored. Components and connections that no deployment
  /// made (from startComponents / connectPorts) are left alone unless `name` lists them.
  /// Under a placement, a deployment whose components are all remote is another host's: applying
  /// it does nothing here; one that runs components of two hosts, or whose connections name a
  /// remote component, is refused.
  /// @return the role violations of `name`'s connections (refused instead when strict).
  /// @throws core::Error naming the deployment, the failing entry's file:line and what failed.
  std::vector<LintViolation> applyDeployment(const std::string& name);

  /// Sets every property value of configuration `name`. Every value is checked first (component,
  /// property, type, range, read-only); when any is wrong, none is set and the error lists every
  /// wrong value with its file:line. A running component takes its values between two of its
  /// updates. On the lockstep clock the whole configuration takes effect between two advances;
  /// with threaded activities each component takes its own values between two of its own steps,
  /// so two components may briefly run with old and new values respectively.
  void applyConfiguration(const std::string& name);

  /// Serves `client` (a component of this configurator): its switch requests are carried out
  /// between steps and answered. Components this configurator creates are attached already.
  /// @throws core::Error when `client` is not one of its components.
  void attachClient(core::Component& client);
  /// Carries out every queued switch request and answers it. Runs by itself between instants of
  /// the lockstep clock and on the service thread in real time; callable directly (tests).
  /// @return true when there was at least one request.
  bool serviceRequests();

  /// The deployment last applied in `scope` (see DeploymentSpec::scope), or "".
  const std::string& currentDeployment(std::string_view scope = {}) const;
  /// The configuration last applied, or "".
  const std::string& currentConfiguration() const { return current_configuration_; }
  /// How many deployments and configurations were applied so far: an observer that sees the same
  /// count again knows currentDeployment() and currentConfiguration() are what they were.
  std::uint64_t switchCount() const { return switch_count_.load(std::memory_order_acquire); }

  /// The lockstep clock (Simulation and WallClock). @throws core::Error in ClockMode::RealTime.
  core::LockstepClock& clock();
  ClockMode mode() const { return options_.mode; }
  /// This process's host (ConfiguratorOptions::host; "" = not split).
  const std::string& host() const { return options_.host; }
  PackageRegistry& packages() { return packages_; }
  const PackageRegistry& packages() const { return packages_; }
  /// Non-fatal findings so far (role violations, adjusted priorities, refused switches: "SUP
  /// asked for configuration 'NAME': why"), oldest first. Not for another thread while switches
  /// are served: see lastWarningWith.
  const std::vector<std::string>& warnings() const { return warnings_; }
  /// The newest warning that contains `text` ("" if none), under the configurator's lock: a run's
  /// observer thread may ask while the executor's thread serves switches.
  std::string lastWarningWith(std::string_view text) const;

 private:
  /// A connection this configurator made, by port path (components may be replaced by name).
  struct Connection {
    std::string output;
    std::string input;
    core::ConnPolicy policy;
    SourceLocation where;
    bool from_deployment = false;  ///< made by applyDeployment (removed when switching away)
    std::string scope;             ///< from_deployment: the scope of the deployment that made it
  };
  /// The checked form of one connection entry.
  struct ResolvedConnection {
    core::PortBase* output;
    core::PortBase* input;
    core::ConnPolicy policy;
    const ConnectionSpec* spec;
  };

  core::Component& component(const std::string& name, const SourceLocation& where) const;
  /// A local component or a remote one's shadow (for checks).
  core::Component& anyComponent(const std::string& name, const SourceLocation& where) const;
  /// Makes the transport ends of the connection `c` between hosts (local output or local input).
  void connectAcrossHosts(const ResolvedConnection& c, detail::UndoJournal& journal);
  /// Throws when a deployment mixes hosts; true when it is all remote (another host's).
  bool isOtherHostsDeployment(const DeploymentSpec& next) const;
  core::PortBase& port(const std::string& path, const SourceLocation& where) const;
  ResolvedConnection resolve(const ConnectionSpec& spec) const;
  /// Throws what a connection of `c` would fail with (direction, type, duplicate, capacity).
  void checkConnection(const ResolvedConnection& c) const;
  /// Checks `spec` and returns it with the priority adjusted; `running_ok` allows a Running
  /// component (the deployment switch restarts it).
  ActivitySpec checkActivity(const ActivitySpec& spec, bool running_ok) const;
  /// Gives the component the activity of `spec` (it must not be Running).
  void applyActivity(core::Component& component, const ActivitySpec& spec);
  /// Takes the component off the clock and gives it a SlaveActivity (undoes a first activity).
  void removeActivity(core::Component& component);
  /// core::Component::setActivity, made safe against writers running on other threads.
  void replaceActivity(core::Component& component, std::unique_ptr<core::Activity> activity);
  /// The default (event-driven) activity for a component started without one.
  ActivitySpec defaultActivity(const std::string& name, const SourceLocation& where) const;
  /// The role violations of `connections`; throws them in strict mode, else records warnings.
  std::vector<LintViolation> checkRoles(const std::vector<ConnectionSpec>& connections);
  /// Split over hosts: the role violations of the connections this host makes an end of, those
  /// crossing hosts linted with the far end's shadow and naming both hosts.
  std::vector<LintViolation> lintOnThisHost(const std::vector<ConnectionSpec>& connections) const;
  void checkConfiguration(const ConfigurationSpec& configuration) const;
  struct DeploymentPlan;
  /// Checks `next` against the current state and lists what switching to it changes.
  DeploymentPlan planDeployment(const DeploymentSpec& next) const;
  /// Makes the changes of `plan`, recording how to undo each in `journal`.
  void carryOut(const DeploymentPlan& plan, const DeploymentSpec& next, detail::UndoJournal& journal);
  void stopAll() noexcept;
  friend class ConfiguratorClient;
  /// Wakes the service thread (real time); real-time safe. Called by ConfiguratorClient.
  void wakeService() noexcept;
  void serviceLoop();

  ConfiguratorOptions options_;
  PackageRegistry packages_;
  // Declared before the components so that it outlives them (their activities point to it).
  std::unique_ptr<core::LockstepClock> clock_;
  core::ComponentRegistry components_;
  DeploymentSet set_;
  std::map<std::string, std::vector<std::string>, std::less<>> peers_;
  std::map<std::string, ActivitySpec, std::less<>> activities_;
  std::map<std::string, std::string, std::less<>> types_;  // instance name -> component type
  std::vector<Connection> connections_;
  std::vector<std::string> started_;  // start order, for stopping in reverse
  std::map<std::string, std::string, std::less<>> current_deployments_;  // scope -> deployment
  std::string current_configuration_;
  std::vector<std::string> warnings_;
  std::optional<Placement> placement_;
  core::ComponentRegistry remote_;  // shadows of the remote components
  std::vector<std::string> writer_topics_, reader_topics_;
  core::ClockSync* clock_sync_ = nullptr;
  ExecutorSpec executor_;
  core::Component* executor_monitor_ = nullptr;  // owned by components_
  core::RealtimeExecutor* handover_watcher_ = nullptr;  // watchHandovers

  mutable std::recursive_mutex mutex_;  // serialises the public operations (see the class comment)
  std::vector<std::pair<core::Component*, ConfiguratorClient*>> clients_;
  std::atomic<std::uint32_t> service_wakeups_{0};
  std::atomic<std::uint64_t> switch_count_{0};  // see switchCount()
  /// service_wakeups_ when the lockstep clock's between-instants hook last serviced: the hook,
  /// run twice per simulated instant, services only when a request came since (no lock, no scan).
  std::uint32_t hook_serviced_wakeups_ = 0;
  std::atomic<bool> service_stopping_{false};
  std::thread service_thread_;  // real time only, started with the first client
};

}  // namespace cobra::deploy
