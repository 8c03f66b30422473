#include "cobra/core/introspection.hpp"

#include <algorithm>
#include <sstream>

#include "cobra/core/activity.hpp"

namespace cobra::core {

ComponentInfo describe(const Component& component) {
  ComponentInfo info{component.name(), component.role(), component.doc(), component.state(),
                     component.activity().describe(), component.lastError(), {}, {}, {}};
  for (const PortBase* port : component.ports()) {
    PortInfo p{port->name(), port->direction(), std::string(port->type().name), port->type().kind,
               port->unit(), port->doc(), port->isEventPort(), {}};
    for (const auto& channel : port->connections()) {
      const PortBase& peer = &channel->writer() == port ? channel->reader() : channel->writer();
      p.connections.push_back({peer.fullName(), channel->policy().describe()});
    }
    info.ports.push_back(std::move(p));
  }
  for (const PropertyBase* property : component.properties())
    info.properties.push_back({property->name(), std::string(property->type().name), property->valueText(),
                               property->unit(), property->doc(), property->rangeText(), property->isReadOnly()});
  for (const OperationBase* op : component.operations())
    info.operations.push_back({op->name(), op->signature(), op->doc(), op->thread()});
  return info;
}

std::string toText(const ComponentInfo& info) {
  std::ostringstream out;
  out << info.name << " [" << toString(info.role) << ", " << toString(info.state) << ", " << info.activity << "]\n";
  if (!info.doc.empty()) out << "  " << info.doc << "\n";
  if (!info.last_error.empty()) out << "  last error: " << info.last_error << "\n";
  for (const PortInfo& p : info.ports) {
    out << "  " << (p.direction == PortDirection::Input ? (p.event_port ? "in(event) " : "in        ") : "out       ")
        << p.name << " : " << p.type;
    if (!p.unit.empty()) out << " [" << p.unit << "]";
    for (const ConnectionInfo& c : p.connections) out << (p.direction == PortDirection::Input ? " <- " : " -> ") << c.peer << " (" << c.policy << ")";
    out << "  -- " << p.doc << "\n";
  }
  for (const PropertyInfo& p : info.properties) {
    out << "  property  " << p.name << " : " << p.type << " = " << p.value;
    if (!p.unit.empty()) out << " [" << p.unit << "]";
    if (!p.range.empty()) out << " in " << p.range;
    if (p.read_only) out << " (read-only)";
    out << "  -- " << p.doc << "\n";
  }
  for (const OperationInfo& o : info.operations) out << "  operation " << o.signature << "  -- " << o.doc << "\n";
  return out.str();
}

ComponentRegistry::~ComponentRegistry() {
  // Stop everything first so no update runs while its peers are being destroyed.
  for (auto& c : components_)
    if (c->isRunning()) (void)c->stop();
  by_name_.clear();
  for (auto it = components_.rbegin(); it != components_.rend(); ++it) it->reset();
}

Component& ComponentRegistry::add(std::unique_ptr<Component> component) {
  if (!component) throw Error("ComponentRegistry::add needs a component, got none");
  if (find(component->name()) != nullptr)
    throw Error("a component named '" + component->name() + "' already exists; names must be unique");
  by_name_.emplace(component->name(), component.get());
  components_.push_back(std::move(component));
  return *components_.back();
}

Component* ComponentRegistry::find(std::string_view name) const {
  const auto it = by_name_.find(std::string(name));
  return it == by_name_.end() ? nullptr : it->second;
}

Component& ComponentRegistry::get(std::string_view name) const {
  if (Component* c = find(name)) return *c;
  std::string names;
  for (const auto& c : components_) names += (names.empty() ? "" : ", ") + c->name();
  throw Error("no component named '" + std::string(name) + "'; the components are: " + (names.empty() ? "(none)" : names));
}

bool ComponentRegistry::remove(std::string_view name) {
  auto it = std::find_if(components_.begin(), components_.end(), [&](const auto& c) { return c->name() == name; });
  if (it == components_.end()) return false;
  if ((*it)->isRunning()) (void)(*it)->stop();
  for (PortBase* port : (*it)->ports()) port->disconnect();
  by_name_.erase((*it)->name());
  components_.erase(it);
  return true;
}

std::vector<Component*> ComponentRegistry::components() const {
  std::vector<Component*> out;
  for (const auto& c : components_) out.push_back(c.get());
  return out;
}

std::vector<ComponentInfo> ComponentRegistry::describeAll() const {
  std::vector<ComponentInfo> out;
  for (const auto& c : components_) out.push_back(describe(*c));
  return out;
}

}  // namespace cobra::core
