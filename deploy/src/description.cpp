#include "cobra/deploy/description.hpp"

#include <algorithm>
#include <map>
#include <memory>
#include <set>
#include <utility>

namespace cobra::deploy {
namespace {

using PortPair = std::pair<std::string, std::string>;

/// What the applied deployments bring back by themselves (applyDeployment), so the rest of the
/// description leaves it out.
struct AppliedDeployments {
  std::vector<std::string> names;
  std::set<std::string, std::less<>> components;
  std::set<PortPair> connections;
  std::map<std::string, ActivitySpec, std::less<>> activities;
};

AppliedDeployments appliedDeployments(const Configurator& configurator) {
  AppliedDeployments applied;
  const DeploymentSet& set = configurator.deploymentSet();
  std::vector<std::string> scopes;
  for (const std::string& name : set.deploymentNames()) {
    const std::string& scope = set.deployment(name).scope;
    if (std::find(scopes.begin(), scopes.end(), scope) == scopes.end()) scopes.push_back(scope);
  }
  for (const std::string& scope : scopes) {
    const std::string& current = configurator.currentDeployment(scope);
    if (current.empty()) continue;
    const DeploymentSpec& spec = set.deployment(current);
    applied.names.push_back(current);
    for (const NameEntry& c : spec.components) applied.components.insert(c.name);
    for (const ConnectionSpec& c : spec.connections) applied.connections.emplace(c.output, c.input);
    for (const ActivitySpec& a : spec.activities) applied.activities.insert_or_assign(a.peer_name, a);
  }
  return applied;
}

/// The property values of a freshly made component of each type, by type then property name.
class Defaults {
 public:
  explicit Defaults(const PackageRegistry& packages) : packages_(packages) {}

  /// The default text of `property` of `type`, or nullptr when a fresh component has none.
  const core::PropertyInfo* find(const std::string& type, const std::string& property) {
    auto it = by_type_.find(type);
    if (it == by_type_.end()) {
      std::vector<core::PropertyInfo> properties;
      try {
        const auto probe = packages_.create(type, "describe_probe");
        properties = core::describe(*probe).properties;
      } catch (const std::exception&) {
        // A type that cannot be made here: every value is written (none is known to be default).
      }
      it = by_type_.emplace(type, std::move(properties)).first;
    }
    for (const core::PropertyInfo& p : it->second)
      if (p.name == property) return &p;
    return nullptr;
  }
  bool known(const std::string& type) const {
    const auto it = by_type_.find(type);
    return it != by_type_.end() && !it->second.empty();
  }

 private:
  const PackageRegistry& packages_;
  std::map<std::string, std::vector<core::PropertyInfo>, std::less<>> by_type_;
};

}  // namespace

ConnPolicySpec connPolicySpecOf(const core::ConnPolicy& policy) {
  ConnPolicySpec spec;
  switch (policy.kind) {
    case core::ConnPolicy::Kind::Data: spec.type = "data"; break;
    case core::ConnPolicy::Kind::Buffer: spec.type = "buffer"; break;
    case core::ConnPolicy::Kind::Circular: spec.type = "circular"; break;
  }
  spec.size = static_cast<int>(policy.size);
  spec.transport = policy.transport;
  spec.topic = policy.topic;
  spec.qos = policy.options;
  return spec;
}

DeploymentDescription describe(const Configurator& configurator) {
  DeploymentDescription d;
  const core::ComponentRegistry& registry = configurator.getReferences();
  const AppliedDeployments applied = appliedDeployments(configurator);
  Defaults defaults(configurator.packages());

  d.packages = configurator.packages().loadedPackages();
  d.executor = configurator.executorSpec();
  d.executor.where = {};
  // The executor's component is setExecutor's, not a package's.
  const auto made_by_setExecutor = [&](const core::Component* c) { return c == configurator.executorMonitor(); };
  for (const core::Component* c : registry.components()) {
    if (made_by_setExecutor(c)) continue;
    const std::string type = configurator.componentTypeOf(c->name());
    d.components.push_back({c->name(), type, {}});
    for (const core::PropertyInfo& p : core::describe(*c).properties) {
      if (p.read_only) continue;
      const core::PropertyInfo* fresh = defaults.find(type, p.name);
      if (fresh == nullptr && defaults.known(type)) continue;  // made at configure, not settable before
      if (fresh != nullptr && fresh->value == p.value) continue;
      d.properties.push_back({c->name(), p.name, p.type, p.value});
    }
  }
  for (const core::Component* c : registry.components()) {
    const ActivitySpec* a = configurator.activityOf(c->name());
    if (a == nullptr) continue;
    const auto by_deployment = applied.activities.find(c->name());
    if (by_deployment != applied.activities.end() ? by_deployment->second.sameActivity(*a)
                                                  : a->sameActivity(ActivitySpec{}))
      continue;  // what the deployment sets, or the event-driven activity every component starts with
    ActivitySpec activity = *a;
    activity.where = {};
    d.activities.push_back(std::move(activity));
  }
  for (const core::Component* c : registry.components()) {
    const auto& peers = configurator.peersOf(c->name());
    if (!peers.empty()) d.peers.push_back({c->name(), peers, {}});
  }
  for (ConnectionSpec& c : configurator.madeConnections()) {
    if (applied.connections.count({c.output, c.input}) != 0) continue;
    c.where = {};
    d.connections.push_back(std::move(c));
  }
  for (const core::Component* c : registry.components())
    for (const core::PortBase* port : c->ports()) {
      if (port->direction() != core::PortDirection::Output) continue;
      for (const auto& channel : port->connections()) {
        const core::Component* owner = channel->reader().owner();
        if (owner == nullptr || registry.find(owner->name()) != owner) ++d.outside_connections;
      }
    }
  const DeploymentSet& set = configurator.deploymentSet();
  for (const std::string& name : set.deploymentNames()) d.deployments.push_back(set.deployment(name));
  for (const std::string& name : set.configurationNames()) d.configurations.push_back(set.configuration(name));
  for (const core::Component* c : registry.components()) {
    // Configured before the deployments apply: a component may make ports when it configures
    // (from its properties) that a deployment connects.
    if (made_by_setExecutor(c)) continue;
    if (c->state() == core::State::Stopped || c->state() == core::State::Running) d.configure.push_back(c->name());
    if (c->state() == core::State::Running && applied.components.count(c->name()) == 0) d.start.push_back(c->name());
  }
  d.apply = applied.names;
  d.configuration = configurator.currentConfiguration();
  return d;
}

DeploymentDescription canonical(DeploymentDescription d) {
  std::map<std::string, std::size_t, std::less<>> order;
  for (const ComponentSpec& c : d.components) order.emplace(c.peer_name, order.size());
  const auto rank = [&](const std::string& name) {
    const auto it = order.find(name);
    return it == order.end() ? order.size() : it->second;
  };
  std::sort(d.deployments.begin(), d.deployments.end(),
            [](const DeploymentSpec& a, const DeploymentSpec& b) { return a.name < b.name; });
  std::sort(d.configurations.begin(), d.configurations.end(),
            [](const ConfigurationSpec& a, const ConfigurationSpec& b) { return a.name < b.name; });
  // Applied deployments: in the order describe finds their scopes.
  std::vector<std::string> apply;
  for (const DeploymentSpec& s : d.deployments)
    if (std::find(d.apply.begin(), d.apply.end(), s.name) != d.apply.end()) apply.push_back(s.name);
  d.apply = apply;
  std::set<std::string, std::less<>> deployed;
  std::set<PortPair> deployed_connections;
  std::map<std::string, ActivitySpec, std::less<>> deployed_activities;
  for (const DeploymentSpec& s : d.deployments) {
    if (std::find(d.apply.begin(), d.apply.end(), s.name) == d.apply.end()) continue;
    for (const NameEntry& c : s.components) deployed.insert(c.name);
    for (const ConnectionSpec& c : s.connections) deployed_connections.emplace(c.output, c.input);
    for (const ActivitySpec& a : s.activities) deployed_activities.insert_or_assign(a.peer_name, a);
  }
  std::erase_if(d.connections, [&](const ConnectionSpec& c) { return deployed_connections.count({c.output, c.input}) != 0; });
  std::erase_if(d.activities, [&](const ActivitySpec& a) {
    const auto by_deployment = deployed_activities.find(a.peer_name);
    return by_deployment != deployed_activities.end() ? by_deployment->second.sameActivity(a) : a.sameActivity(ActivitySpec{});
  });
  const auto byComponent = [&](const auto& a, const auto& b) { return rank(a.peer_name) < rank(b.peer_name); };
  std::stable_sort(d.activities.begin(), d.activities.end(), byComponent);
  std::stable_sort(d.peers.begin(), d.peers.end(), byComponent);
  std::set<std::string, std::less<>> configured(d.configure.begin(), d.configure.end());
  configured.insert(d.start.begin(), d.start.end());
  configured.insert(deployed.begin(), deployed.end());
  const std::set<std::string, std::less<>> started(d.start.begin(), d.start.end());
  d.configure.clear();
  d.start.clear();
  for (const ComponentSpec& c : d.components) {
    if (configured.count(c.peer_name) != 0) d.configure.push_back(c.peer_name);
    if (started.count(c.peer_name) != 0 && deployed.count(c.peer_name) == 0) d.start.push_back(c.peer_name);
  }
  return d;
}

}  // namespace cobra::deploy
