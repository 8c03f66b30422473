// The run-time switch between named deployments and configurations (thesis §2.2.3).

#include <algorithm>
#include <optional>
#include <set>

#include "cobra/deploy/configurator.hpp"
#include "cobra/deploy/suggest.hpp"
#include "undo_journal.hpp"

namespace cobra::deploy {
namespace {

std::string quoted(const std::string& name) { return "'" + name + "'"; }

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

void throwIfFailed(const core::Result& result) {
  if (!result) throw core::Error(result.message);
}

}  // namespace

void Configurator::checkConfiguration(const ConfigurationSpec& configuration) const {
  std::string errors;
  std::map<std::string, SourceLocation, std::less<>> seen;
  for (const PropertyValueSpec& value : configuration.values) {
    try {
      const std::string key = value.component + "." + value.property;
      if (const auto it = seen.find(key); it != seen.end())
        throw core::Error(value.where.text() + ": " + key + " is already set at " + it->second.text() +
                          "; set each property once per configuration");
      seen.emplace(key, value.where);
      core::Component& c = anyComponent(value.component, value.where);  // a remote one's values are checked too
      core::PropertyBase* property = c.findProperty(value.property);
      if (property == nullptr) {
        std::vector<std::string> names;
        for (const core::PropertyBase* p : c.properties()) names.push_back(p->name());
        throw core::Error(value.where.text() + ": component " + quoted(c.name()) + " has no property " +
                          quoted(value.property) + suggestionText(value.property, names, "properties"));
      }
      try {
        property->checkText(value.value);
      } catch (const std::exception& e) {
        throw core::Error(value.where.text() + ": " + e.what());
      }
    } catch (const std::exception& e) {
      errors += std::string("\n  ") + e.what();
    }
  }
  if (!errors.empty())
    throw core::Error("configuration " + quoted(configuration.name) + " (" + configuration.where.text() +
                      ") has wrong values:" + errors);
}

void Configurator::applyConfiguration(const std::string& name) {
  const std::lock_guard lock(mutex_);
  const ConfigurationSpec& configuration = set_.configuration(name);
  try {
    checkConfiguration(configuration);
  } catch (const std::exception& e) {
    throw core::Error(std::string(e.what()) + "\nnothing was applied");
  }
  detail::UndoJournal journal;
  for (const PropertyValueSpec& value : configuration.values) {
    if (isRemote(value.component)) continue;  // its host sets it
    core::PropertyBase& property = component(value.component, value.where).property(value.property);
    const std::string before = property.valueText();
    try {
      property.setFromText(value.value);
    } catch (const std::exception& e) {
      journal.fail(value.where.text() + ": configuration " + quoted(name) + ": " + e.what());
    }
    journal.record(value.component + "." + value.property, [&property, before] { property.setFromText(before); });
  }
  current_configuration_ = name;
  switch_count_.fetch_add(1, std::memory_order_release);
}

/// What a deployment switch changes, computed before anything changes.
struct Configurator::DeploymentPlan {
  std::vector<std::string> run;            ///< components of the next deployment, in start order
  std::vector<ActivitySpec> activities;    ///< checked activities of the next deployment
  std::vector<std::string> stop;           ///< running components to stop, in stop order
  std::vector<Connection> removals;        ///< deployment connections the next one does not have
  std::vector<ResolvedConnection> additions;

  /// The new activity of `name` when it differs from `current`, else nullptr.
  const ActivitySpec* activityChange(const std::string& name,
                                     const std::map<std::string, ActivitySpec, std::less<>>& current) const {
    for (const ActivitySpec& a : activities) {
      if (a.peer_name != name) continue;
      const auto it = current.find(name);
      return it != current.end() && it->second.sameActivity(a) ? nullptr : &a;
    }
    return nullptr;
  }
};

Configurator::DeploymentPlan Configurator::planDeployment(const DeploymentSpec& next) const {
  DeploymentPlan plan;
  for (const NameEntry& entry : next.components) {
    core::Component& c = component(entry.name, entry.where);
    if (contains(plan.run, c.name()))
      throw core::Error(entry.where.text() + ": " + quoted(c.name()) + " is listed twice; list each component once");
    if (c.state() == core::State::Exception || c.state() == core::State::FatalError)
      throw core::Error(entry.where.text() + ": " + quoted(c.name()) + " is " + std::string(core::toString(c.state())) +
                        " (" + c.lastError() + "); recover it first");
    plan.run.push_back(c.name());
  }
  for (const ActivitySpec& spec : next.activities) {
    if (!contains(plan.run, spec.peer_name))
      throw core::Error(spec.where.text() + ": activity for " + quoted(spec.peer_name) +
                        ", which this deployment does not run; add it to the deployment's components");
    if (std::any_of(plan.activities.begin(), plan.activities.end(),
                    [&](const ActivitySpec& a) { return a.peer_name == spec.peer_name; }))
      throw core::Error(spec.where.text() + ": " + quoted(spec.peer_name) + " has two activities; give it one");
    plan.activities.push_back(checkActivity(spec, true));
  }
  // A component runs in the deployments of one scope only: another scope's switch would stop it.
  for (const auto& [scope, current] : current_deployments_) {
    if (scope == next.scope) continue;
    const DeploymentSpec& other = set_.deployment(current);
    for (const NameEntry& entry : next.components)
      if (std::any_of(other.components.begin(), other.components.end(),
                      [&](const NameEntry& e) { return e.name == entry.name; }))
        throw core::Error(entry.where.text() + ": " + quoted(entry.name) + " is run by deployment " + quoted(current) +
                          " of scope " + quoted(scope) +
                          "; a component belongs to the deployments of one scope (start it outside deployments to share it)");
  }
  std::vector<const Connection*> kept;
  for (const ConnectionSpec& spec : next.connections) {
    ResolvedConnection c = resolve(spec);
    for (const core::PortBase* p : {c.output, c.input})
      if (isRemote(p->owner()->name()))
        throw core::Error(spec.where.text() + ": " + spec.output + " -> " + spec.input + " names " +
                          quoted(p->owner()->name()) + " of host '" + placement_->hostOf(p->owner()->name(), spec.where) +
                          "'; a deployment switches the connections of its own host: make connections between hosts "
                          "with connectPorts");
    if (std::any_of(plan.additions.begin(), plan.additions.end(),
                    [&](const ResolvedConnection& a) { return a.output == c.output && a.input == c.input; }))
      throw core::Error(spec.where.text() + ": " + spec.output + " -> " + spec.input + " appears twice");
    const auto made = std::find_if(connections_.begin(), connections_.end(), [&](const Connection& m) {
      return m.from_deployment && m.output == spec.output && m.input == spec.input;
    });
    if (made != connections_.end() && made->scope != next.scope)
      throw core::Error(spec.where.text() + ": " + spec.output + " -> " + spec.input +
                        " is made by a deployment of scope " + quoted(made->scope) +
                        "; a connection belongs to the deployments of one scope");
    if (made != connections_.end() && made->policy == c.policy) {
      kept.push_back(&*made);
      continue;
    }
    if (made == connections_.end()) checkConnection(c);  // one with another policy was checked when made
    plan.additions.push_back(c);
  }
  for (const Connection& m : connections_)
    if (m.from_deployment && m.scope == next.scope && std::find(kept.begin(), kept.end(), &m) == kept.end())
      plan.removals.push_back(m);

  const std::string& current = currentDeployment(next.scope);
  const DeploymentSpec* previous = current.empty() ? nullptr : set_.findDeployment(current);
  if (previous != nullptr)
    for (auto it = previous->components.rbegin(); it != previous->components.rend(); ++it)
      if (!contains(plan.run, it->name)) plan.stop.push_back(it->name);
  for (const std::string& n : plan.run)
    if (plan.activityChange(n, activities_) != nullptr) plan.stop.push_back(n);  // restarted with the new one
  return plan;
}

void Configurator::carryOut(const DeploymentPlan& plan, const DeploymentSpec& next, detail::UndoJournal& journal) {
  // Each step names the entry it comes from; the caller undoes the journal when one throws.
  auto step = [](const SourceLocation& where, const std::string& what, const std::function<void()>& action) {
    try {
      action();
    } catch (const std::exception& e) {
      throw core::Error(where.text() + ": " + what + ": " + e.what());
    }
  };
  for (const std::string& n : plan.stop) {
    core::Component& c = component(n, next.where);
    if (!c.isRunning()) continue;
    step(next.where, "cannot stop " + quoted(n), [&] { throwIfFailed(c.stop()); });
    std::erase(started_, n);
    journal.record("the stop of " + quoted(n), [this, &c] {
      throwIfFailed(c.start());
      started_.push_back(c.name());
    });
  }
  for (const Connection& m : plan.removals) {
    core::PortBase& output = port(m.output, m.where);
    core::PortBase& input = port(m.input, m.where);
    core::disconnectPorts(output, input);
    std::erase_if(connections_, [&](const Connection& c) { return c.output == m.output && c.input == m.input; });
    journal.record("the removal of " + m.output + " -> " + m.input, [this, &output, &input, m] {
      core::connectPorts(output, input, m.policy);
      connections_.push_back(m);
    });
  }
  for (const std::string& n : plan.run) {
    const ActivitySpec* change = plan.activityChange(n, activities_);
    if (change == nullptr) continue;
    core::Component& c = component(n, change->where);
    std::optional<ActivitySpec> before;
    if (const auto it = activities_.find(n); it != activities_.end()) before = it->second;
    step(change->where, "cannot set the activity of " + quoted(n), [&] { applyActivity(c, *change); });
    journal.record("the activity of " + quoted(n), [this, &c, before] {
      if (before) applyActivity(c, *before);
      else removeActivity(c);
    });
  }
  for (const NameEntry& entry : next.components) {
    core::Component& c = component(entry.name, entry.where);
    if (c.isRunning() || activities_.count(c.name()) != 0) continue;
    step(entry.where, "cannot give " + quoted(c.name()) + " an activity",
         [&] { applyActivity(c, defaultActivity(c.name(), entry.where)); });
    journal.record("the default activity of " + quoted(c.name()), [this, &c] { removeActivity(c); });
  }
  for (const ResolvedConnection& a : plan.additions) {
    step(a.spec->where, "cannot connect " + a.spec->output + " -> " + a.spec->input,
         [&] { core::connectPorts(*a.output, *a.input, a.policy); });
    connections_.push_back({a.spec->output, a.spec->input, a.policy, a.spec->where, true, next.scope});
    journal.record("the connection " + a.spec->output + " -> " + a.spec->input, [this, a] {
      core::disconnectPorts(*a.output, *a.input);
      std::erase_if(connections_,
                    [&](const Connection& c) { return c.output == a.spec->output && c.input == a.spec->input; });
    });
  }
  for (const NameEntry& entry : next.components) {
    core::Component& c = component(entry.name, entry.where);
    if (c.isRunning()) continue;
    if (c.state() == core::State::PreOperational) {
      step(entry.where, "cannot configure " + quoted(c.name()), [&] {
        if (const core::Result r = c.configure(); !r) {
          throw core::Error(r.message + detail::recoverAfterFailure(c));
        }
      });
      journal.record("the configuration of " + quoted(c.name()), [&c] { throwIfFailed(c.cleanup()); });
    }
  }
  for (const NameEntry& entry : next.components) {
    core::Component& c = component(entry.name, entry.where);
    if (c.isRunning()) continue;
    step(entry.where, "cannot start " + quoted(c.name()), [&] {
      if (const core::Result r = c.start(); !r) {
        throw core::Error(r.message + detail::recoverAfterFailure(c, true));
      }
    });
    started_.push_back(c.name());
    journal.record("the start of " + quoted(c.name()), [this, &c] {
      std::erase(started_, c.name());
      throwIfFailed(c.stop());
    });
  }
}

std::vector<LintViolation> Configurator::applyDeployment(const std::string& name) {
  const std::lock_guard lock(mutex_);
  const DeploymentSpec& next = set_.deployment(name);
  const std::string context = "deployment " + quoted(name) + " (" + next.where.text() + ") not applied: ";
  DeploymentPlan plan;
  std::vector<LintViolation> violations;
  try {
    if (isOtherHostsDeployment(next)) return violations;
    plan = planDeployment(next);
    violations = checkRoles(next.connections);
  } catch (const std::exception& e) {
    throw core::Error(context + e.what() + "; nothing was changed");
  }
  detail::UndoJournal journal;
  try {
    carryOut(plan, next, journal);
  } catch (const std::exception& e) {
    journal.fail(context + e.what());  // the previous deployment runs again
  }
  current_deployments_[next.scope] = name;
  switch_count_.fetch_add(1, std::memory_order_release);
  return violations;
}

bool Configurator::isOtherHostsDeployment(const DeploymentSpec& next) const {
  if (!placement_ || next.components.empty()) return false;
  std::map<std::string, std::vector<std::string>> by_host;  // host -> components ("" everywhere)
  for (const NameEntry& entry : next.components) {
    (void)anyComponent(entry.name, entry.where);
    by_host[placement_->hostOf(entry.name, entry.where)].push_back(entry.name);
  }
  by_host.erase("");  // an everywhere component runs on every host, with each host's deployment
  if (by_host.size() > 1) {
    std::string hosts;
    for (const auto& [host, names] : by_host) {
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
      hosts += (hosts.empty() ? "" : "; ") + std::string("host '") + host + "': " + list;
    }
    throw core::Error(next.where.text() + ": it runs components of " + std::to_string(by_host.size()) +
                      " hosts (" + hosts + "); a deployment is switched by one process, so it runs one host's "
                      "components: split it per host");
  }
  return !by_host.empty() && by_host.begin()->first != placement_->host();
}

const std::string& Configurator::currentDeployment(std::string_view scope) const {
  static const std::string none;
  const auto it = current_deployments_.find(scope);
  return it == current_deployments_.end() ? none : it->second;
}

}  // namespace cobra::deploy
