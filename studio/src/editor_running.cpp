// GET /api/editor/running: the running deployment, described at setup on the run's thread,
// following the run's deployment switches, with the property values and component states of the
// moment (editor.hpp, RunningDeployment).

#include <algorithm>
#include <map>

#include "cobra/core/introspection.hpp"
#include "cobra/studio/editor.hpp"

namespace cobra::studio {
namespace {

/// The scopes of `d`'s named deployments, in order of their first deployment ("" first when the
/// description has none, so that a run without named deployments still has the default scope).
std::vector<std::pair<std::string, std::string>> scopesOf(const deploy::DeploymentDescription& d) {
  std::vector<std::pair<std::string, std::string>> scopes;
  for (const deploy::DeploymentSpec& spec : d.deployments)
    if (std::none_of(scopes.begin(), scopes.end(), [&](const auto& s) { return s.first == spec.scope; }))
      scopes.emplace_back(spec.scope, "");
  if (scopes.empty()) scopes.emplace_back("", "");
  return scopes;
}

const deploy::DeploymentSpec* deploymentNamed(const deploy::DeploymentDescription& d, const std::string& name) {
  for (const deploy::DeploymentSpec& spec : d.deployments)
    if (spec.name == name) return &spec;
  return nullptr;
}

}  // namespace

RunningDeployment::RunningDeployment(run::RunObserver* inner) : inner_(inner) {}
RunningDeployment::~RunningDeployment() = default;

void RunningDeployment::attach(const run::RunContext& run) {
  if (run.configurator != nullptr) {
    // On the run's thread, before its first step: the Configurator is not changing.
    deploy::DeploymentDescription d = deploy::describe(*run.configurator);
    std::vector<std::pair<std::string, std::string>> values;
    for (const core::Component* c : run.registry.components())
      for (const core::PropertyInfo& p : core::describe(*c).properties)
        if (!p.read_only) values.emplace_back(c->name() + "." + p.name, p.value);
    configurator_ = run.configurator;
    switches_seen_ = configurator_->switchCount();
    staged_ = InForce{};
    staged_.deployments = scopesOf(d);
    for (auto& [scope, deployment] : staged_.deployments) deployment = configurator_->currentDeployment(scope);
    staged_.configuration = configurator_->currentConfiguration();
    const std::lock_guard lock(mutex_);
    description_ = std::move(d);
    attach_values_ = std::move(values);
    registry_ = &run.registry;
    in_force_ = staged_;
  }
  if (inner_ != nullptr) inner_->attach(run);
}

void RunningDeployment::stageSwitch(double t) {
  // Between two instants on the run's thread: the Configurator is not changing. Allocates only
  // when a name is longer than the one it replaces (a switch allocates anyway: it connects ports).
  staged_.t = t;
  ++staged_.switches;
  bool unknown = false;
  for (auto& [scope, deployment] : staged_.deployments) {
    deployment = configurator_->currentDeployment(scope);
    // description_ is written only on this thread (attach, a hand-over below), so reading it
    // here without the lock is safe.
    unknown = unknown || (!deployment.empty() && deploymentNamed(*description_, deployment) == nullptr);
  }
  staged_.configuration = configurator_->currentConfiguration();
  if (unknown) {
    // A deployment defined during the run: describe again (rare; the attach-time one lacks it).
    staged_description_ = deploy::describe(*configurator_);
    const auto scopes = scopesOf(*staged_description_);
    staged_.deployments = scopes;
    for (auto& [scope, deployment] : staged_.deployments) deployment = configurator_->currentDeployment(scope);
  }
  pending_ = true;
}

void RunningDeployment::handOver() {
  // Copies into in_force_'s existing strings (no allocation unless a name grew); `running` is
  // the requests' to fill.
  in_force_.t = staged_.t;
  in_force_.switches = staged_.switches;
  in_force_.deployments = staged_.deployments;
  in_force_.configuration = staged_.configuration;
  if (staged_description_) {
    description_ = std::move(staged_description_);
    staged_description_.reset();
  }
  pending_ = false;
}

void RunningDeployment::step(const run::StepView& now) {
  if (configurator_ != nullptr) {
    const std::uint64_t switches = configurator_->switchCount();
    if (switches != switches_seen_) {
      switches_seen_ = switches;
      stageSwitch(now.t);
    }
    if (pending_) {
      // Never wait for a request reading the description: try again at the next step.
      const std::unique_lock lock(mutex_, std::try_to_lock);
      if (lock.owns_lock()) handOver();
    }
  }
  if (inner_ != nullptr) inner_->step(now);
}

void RunningDeployment::event(double t, const std::string& source, const std::string& name) {
  if (inner_ != nullptr) inner_->event(t, source, name);
}

bool RunningDeployment::nextInput(std::size_t& index) { return inner_ != nullptr && inner_->nextInput(index); }

std::vector<std::string> RunningDeployment::finished(const run::RunResult& result) {
  {
    // The registry goes with the run: keep the values and states of its last instant. A switch
    // staged and not handed over yet is handed over now (the lock may be waited for: the run is over).
    const std::lock_guard lock(mutex_);
    if (pending_) handOver();
    if (description_) refreshValues(*description_, &in_force_.running);
    registry_ = nullptr;
    configurator_ = nullptr;
  }
  return inner_ != nullptr ? inner_->finished(result) : std::vector<std::string>{};
}

void RunningDeployment::refreshValues(deploy::DeploymentDescription& d, std::vector<std::string>* running) const {
  if (registry_ == nullptr) return;
  std::map<std::string, std::string> at_attach(attach_values_.begin(), attach_values_.end());
  std::vector<deploy::PropertyValueDescription> properties;
  if (running != nullptr) running->clear();
  for (const deploy::ComponentSpec& spec : d.components) {
    const core::Component* c = registry_->find(spec.peer_name);
    if (c == nullptr) continue;
    const core::ComponentInfo info = core::describe(*c);
    if (running != nullptr && info.state == core::State::Running) running->push_back(spec.peer_name);
    for (const core::PropertyInfo& p : info.properties) {
      if (p.read_only) continue;
      const std::string key = spec.peer_name + "." + p.name;
      bool listed = false;
      for (const deploy::PropertyValueDescription& v : d.properties)
        listed = listed || (v.component == spec.peer_name && v.property == p.name);
      // Listed at setup (not the default then), or changed since: its value now.
      if (listed || at_attach[key] != p.value) properties.push_back({spec.peer_name, p.name, p.type, p.value});
    }
  }
  d.properties = std::move(properties);
}

std::optional<deploy::DeploymentDescription> RunningDeployment::snapshot(bool& live, InForce* now) const {
  const std::lock_guard lock(mutex_);
  live = registry_ != nullptr;
  if (!description_) return std::nullopt;
  deploy::DeploymentDescription d = *description_;
  InForce in_force = in_force_;
  if (live) refreshValues(d, &in_force.running);
  // The deployments in force are the applied ones (one per scope, in the scopes' order), and the
  // configuration applied last is the one in force.
  d.apply.clear();
  in_force.connections = d.connections;
  for (const auto& [scope, deployment] : in_force.deployments) {
    if (deployment.empty()) continue;
    d.apply.push_back(deployment);
    if (const deploy::DeploymentSpec* spec = deploymentNamed(d, deployment))
      in_force.connections.insert(in_force.connections.end(), spec->connections.begin(), spec->connections.end());
  }
  d.configuration = in_force.configuration;
  if (now != nullptr) *now = std::move(in_force);
  return d;
}

}  // namespace cobra::studio
