// GET /api/editor/running: the running deployment, described at setup on the run's thread, with
// the property values of the moment (editor.hpp, RunningDeployment).

#include <map>

#include "cobra/core/introspection.hpp"
#include "cobra/studio/editor.hpp"

namespace cobra::studio {

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
    const std::lock_guard lock(mutex_);
    description_ = std::move(d);
    attach_values_ = std::move(values);
    registry_ = &run.registry;
  }
  if (inner_ != nullptr) inner_->attach(run);
}

void RunningDeployment::step(const run::StepView& now) {
  if (inner_ != nullptr) inner_->step(now);
}

void RunningDeployment::event(double t, const std::string& source, const std::string& name) {
  if (inner_ != nullptr) inner_->event(t, source, name);
}

bool RunningDeployment::nextInput(std::size_t& index) { return inner_ != nullptr && inner_->nextInput(index); }

std::vector<std::string> RunningDeployment::finished(const run::RunResult& result) {
  {
    // The registry goes with the run: keep the values of its last instant. The lock is only ever
    // held by a request reading values, never while the run steps.
    const std::lock_guard lock(mutex_);
    if (description_) refreshValues(*description_);
    registry_ = nullptr;
  }
  return inner_ != nullptr ? inner_->finished(result) : std::vector<std::string>{};
}

void RunningDeployment::refreshValues(deploy::DeploymentDescription& d) const {
  if (registry_ == nullptr) return;
  std::map<std::string, std::string> at_attach(attach_values_.begin(), attach_values_.end());
  std::vector<deploy::PropertyValueDescription> properties;
  for (const deploy::ComponentSpec& spec : d.components) {
    const core::Component* c = registry_->find(spec.peer_name);
    if (c == nullptr) continue;
    for (const core::PropertyInfo& p : core::describe(*c).properties) {
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

std::optional<deploy::DeploymentDescription> RunningDeployment::snapshot(bool& live) const {
  const std::lock_guard lock(mutex_);
  live = registry_ != nullptr;
  if (!description_) return std::nullopt;
  deploy::DeploymentDescription d = *description_;
  refreshValues(d);
  return d;
}

}  // namespace cobra::studio
