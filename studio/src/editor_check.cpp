// The editor's checks (studio/PROTOCOL.md: check, validate): what the Configurator would refuse,
// said before anything is deployed, and the role linter's verdict (deploy/lint.hpp).

#include <set>

#include "cobra/deploy/lint.hpp"
#include "cobra/deploy/suggest.hpp"
#include "cobra/studio/json.hpp"
#include "editor_internal.hpp"

namespace cobra::studio::editor {
namespace {

const char* directionName(core::PortDirection d) { return d == core::PortDirection::Input ? "an input" : "an output"; }

/// The type of component `name` in `d`, or nullptr.
const std::string* typeOf(const deploy::DeploymentDescription& d, const std::string& name) {
  for (const deploy::ComponentSpec& c : d.components)
    if (c.peer_name == name) return &c.component_type;
  return nullptr;
}

std::vector<std::string> componentNames(const deploy::DeploymentDescription& d) {
  std::vector<std::string> names;
  for (const deploy::ComponentSpec& c : d.components) names.push_back(c.peer_name);
  return names;
}

/// The project's property values of `component` (name, text).
std::vector<std::pair<std::string, std::string>> valuesOf(const deploy::DeploymentDescription& d, const std::string& component) {
  std::vector<std::pair<std::string, std::string>> values;
  for (const deploy::PropertyValueDescription& p : d.properties)
    if (p.component == component) values.emplace_back(p.property, p.value);
  return values;
}

/// Component `name` of `d` as the project makes it: its type with the project's property values,
/// configured (Palette::makeConfigured), so the ports it makes at configure can be connected.
/// A value that cannot be set leaves it as made (validate reports the value).
std::unique_ptr<core::Component> instanceOf(const deploy::DeploymentDescription& d, const std::string& name,
                                            const std::string& type, const Palette& palette) {
  try {
    return palette.makeConfigured(type, name, valuesOf(d, name));
  } catch (const std::exception&) {
    return palette.makeConfigured(type, name, {});
  }
}

/// The port `path` ("Comp.port") of `d`; throws the reason it is not one.
core::PortInfo resolvePort(const deploy::DeploymentDescription& d, const std::string& path, const Palette& palette) {
  const auto dot = path.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == path.size())
    throw std::runtime_error("'" + path + "' is not Component.port");
  const std::string component = path.substr(0, dot), port = path.substr(dot + 1);
  const std::string* type = typeOf(d, component);
  if (type == nullptr)
    throw std::runtime_error("no component '" + component + "' in the project" +
                             deploy::suggestionText(component, componentNames(d), "components"));
  if (palette.find(*type) == nullptr)
    throw std::runtime_error("component '" + component + "' has type '" + *type + "', which no loadable package provides");
  const core::ComponentInfo info = core::describe(*instanceOf(d, component, *type, palette));
  std::vector<std::string> names;
  for (const core::PortInfo& p : info.ports) {
    if (p.name == port) return p;
    names.push_back(p.name);
  }
  throw std::runtime_error("component '" + component + "' (" + *type + ") has no port '" + port + "'" +
                           deploy::suggestionText(port, names, "ports"));
}

/// The reason `c` cannot be made, or "".
std::string refusal(const deploy::DeploymentDescription& d, const deploy::ConnectionSpec& c, const Palette& palette) {
  try {
    const core::PortInfo out = resolvePort(d, c.output, palette);
    const core::PortInfo in = resolvePort(d, c.input, palette);
    if (out.direction != core::PortDirection::Output)
      return "'" + c.output + "' is " + directionName(out.direction) + " port; a connection starts at an output port";
    if (in.direction != core::PortDirection::Input)
      return "'" + c.input + "' is " + directionName(in.direction) + " port; a connection ends at an input port";
    if (out.type != in.type)
      return "types differ: '" + c.output + "' writes " + out.type + ", '" + c.input + "' reads " + in.type;
    (void)deploy::toConnPolicy(c.conn_policy, {});
  } catch (const std::exception& e) {
    std::string reason = e.what();
    if (reason.rfind("<no location>: ", 0) == 0) reason = reason.substr(15);
    return reason;
  }
  return {};
}

/// The role linter on `c` (whose ports exist and match), with components made for the purpose.
std::vector<LintItem> lintOf(const deploy::DeploymentDescription& d, const deploy::ConnectionSpec& c, const Palette& palette) {
  const auto split = [](const std::string& path) {
    const auto dot = path.find('.');
    return std::pair{path.substr(0, dot), path.substr(dot + 1)};
  };
  const auto [out_component, out_port] = split(c.output);
  const auto [in_component, in_port] = split(c.input);
  const auto writer = instanceOf(d, out_component, *typeOf(d, out_component), palette);
  std::unique_ptr<core::Component> reader_own;
  core::Component* reader = writer.get();
  if (in_component != out_component) {
    reader_own = instanceOf(d, in_component, *typeOf(d, in_component), palette);
    reader = reader_own.get();
  }
  std::vector<LintItem> items;
  for (const deploy::LintViolation& v : deploy::lintConnection(*writer->findPort(out_port), *reader->findPort(in_port)))
    items.push_back({v.rule, v.message});
  return items;
}

}  // namespace

ConnectionVerdict checkConnection(const deploy::DeploymentDescription& d, const deploy::ConnectionSpec& c,
                                  const Palette& palette) {
  ConnectionVerdict verdict;
  verdict.reason = refusal(d, c, palette);
  if (verdict.reason.empty()) verdict.lint = lintOf(d, c, palette);
  return verdict;
}

std::vector<Problem> validate(const deploy::DeploymentDescription& d, const Palette& palette, std::vector<LintItem>& lint) {
  std::vector<Problem> problems;
  std::set<std::string> names;
  for (const deploy::ComponentSpec& c : d.components) {
    const std::string where = "component '" + c.peer_name + "'";
    if (!names.insert(c.peer_name).second) problems.push_back({where, "two components have this name"});
    if (palette.find(c.component_type) == nullptr)
      problems.push_back({where, "unknown component type '" + c.component_type + "'" +
                                     deploy::suggestionText(c.component_type, palette.typeNames(), "types")});
  }
  const auto known = [&](const std::string& name) { return names.count(name) != 0; };
  const auto unknown = [&](const std::string& name) {
    return "no component '" + name + "' in the project" + deploy::suggestionText(name, componentNames(d), "components");
  };
  // A property value checked as the component itself would (type, range, read-only).
  const auto checkValue = [&](const std::string& where, const std::string& component, const std::string& property,
                              const std::string& value) {
    const std::string* type = typeOf(d, component);
    const PaletteType* t = type != nullptr ? palette.find(*type) : nullptr;
    if (t == nullptr) {
      if (type == nullptr) problems.push_back({where, unknown(component)});
      return;
    }
    const core::PropertyInfo* info = t->property(property);
    if (info == nullptr) {
      problems.push_back({where, "component '" + component + "' (" + *type + ") has no property '" + property + "'" +
                                     deploy::suggestionText(property, t->propertyNames(), "properties")});
      return;
    }
    if (info->read_only) {
      problems.push_back({where, "property '" + property + "' is read-only (the component sets it itself)"});
      return;
    }
    try {
      palette.make(*type, component)->property(property).checkText(value);
    } catch (const std::exception& e) {
      problems.push_back({where, e.what()});
    }
  };
  for (const deploy::PropertyValueDescription& p : d.properties)
    checkValue("component '" + p.component + "' property '" + p.property + "'", p.component, p.property, p.value);
  const auto checkActivity = [&](const std::string& where, const deploy::ActivitySpec& a) {
    if (!known(a.peer_name)) problems.push_back({where, unknown(a.peer_name)});
    if (!(a.period >= 0.0)) problems.push_back({where, "period must be 0 (event-driven) or more s, got " + std::to_string(a.period)});
    if (a.priority < 0 || a.priority > 99) problems.push_back({where, "priority must be 0..99, got " + std::to_string(a.priority)});
    try {
      (void)deploy::toScheduler(a.scheduler, {});
    } catch (const std::exception& e) {
      std::string message = e.what();
      if (message.rfind("<no location>: ", 0) == 0) message = message.substr(15);
      problems.push_back({where, message});
    }
  };
  for (const deploy::ActivitySpec& a : d.activities) checkActivity("activity of '" + a.peer_name + "'", a);
  for (const deploy::PeerSpec& p : d.peers) {
    if (!known(p.peer_name)) problems.push_back({"peers of '" + p.peer_name + "'", unknown(p.peer_name)});
    for (const std::string& peer : p.peers_to_add)
      if (!known(peer)) problems.push_back({"peers of '" + p.peer_name + "'", unknown(peer)});
  }
  const auto checkConnections = [&](const std::string& prefix, const std::vector<deploy::ConnectionSpec>& connections) {
    for (const deploy::ConnectionSpec& c : connections) {
      const ConnectionVerdict verdict = checkConnection(d, c, palette);
      const std::string where = prefix + "connection '" + c.output + "' -> '" + c.input + "'";
      if (!verdict.reason.empty()) problems.push_back({where, verdict.reason});
      lint.insert(lint.end(), verdict.lint.begin(), verdict.lint.end());
    }
  };
  checkConnections("", d.connections);
  for (const deploy::DeploymentSpec& s : d.deployments) {
    const std::string prefix = "deployment '" + s.name + "' ";
    for (const deploy::NameEntry& c : s.components)
      if (!known(c.name)) problems.push_back({prefix + "components", unknown(c.name)});
    for (const deploy::ActivitySpec& a : s.activities) checkActivity(prefix + "activity of '" + a.peer_name + "'", a);
    checkConnections(prefix, s.connections);
  }
  std::set<std::string> deployments;
  for (const deploy::DeploymentSpec& s : d.deployments) deployments.insert(s.name);
  for (const deploy::ConfigurationSpec& c : d.configurations)
    for (const deploy::PropertyValueSpec& v : c.values)
      checkValue("configuration '" + c.name + "' value '" + v.component + "." + v.property + "'", v.component, v.property, v.value);
  for (const std::string& name : d.apply)
    if (deployments.count(name) == 0) problems.push_back({"apply", "no deployment named '" + name + "' in the project"});
  for (const auto* list : {&d.configure, &d.start})
    for (const std::string& name : *list)
      if (!known(name)) problems.push_back({list == &d.configure ? "configure" : "start", unknown(name)});
  return problems;
}

std::string lintJson(const std::vector<LintItem>& lint) {
  std::string out = "[";
  for (std::size_t i = 0; i < lint.size(); ++i)
    out += std::string(i ? "," : "") + "{\"rule\":" + json::quoted(lint[i].rule) + ",\"message\":" + json::quoted(lint[i].message) + "}";
  return out + "]";
}

}  // namespace cobra::studio::editor
