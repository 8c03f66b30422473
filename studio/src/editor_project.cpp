// The editor's Project JSON (studio/PROTOCOL.md "The editor (v1)") to and from
// deploy::DeploymentDescription, and the layout sidecar.

#include <cmath>
#include <set>

#include "cobra/studio/json.hpp"
#include "editor_internal.hpp"

namespace cobra::studio::editor {
namespace {

std::string stringArray(const std::vector<std::string>& names) {
  std::string out = "[";
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? "," : "") + json::quoted(names[i]);
  return out + "]";
}

std::string number(double value) {
  std::string out;
  json::appendNumber(out, value);
  return out;
}

std::string policyJson(const deploy::ConnPolicySpec& p) {
  std::string out = "{\"type\":" + json::quoted(p.type);
  if (p.type != "data") out += ",\"size\":" + std::to_string(p.size);
  if (!p.transport.empty()) out += ",\"transport\":" + json::quoted(p.transport);
  if (!p.topic.empty()) out += ",\"topic\":" + json::quoted(p.topic);
  if (!p.qos.empty()) {
    out += ",\"qos\":{";
    for (std::size_t i = 0; i < p.qos.size(); ++i)
      out += (i ? "," : "") + json::quoted(p.qos[i].first) + ":" + json::quoted(p.qos[i].second);
    out += "}";
  }
  return out + "}";
}

std::string connectionJson(const deploy::ConnectionSpec& c) {
  return "{\"output\":" + json::quoted(c.output) + ",\"input\":" + json::quoted(c.input) +
         ",\"conn_policy\":" + policyJson(c.conn_policy) + "}";
}

std::string activityJson(const deploy::ActivitySpec& a) {
  return "{\"period\":" + number(a.period) + ",\"priority\":" + std::to_string(a.priority) +
         ",\"scheduler\":" + json::quoted(a.scheduler) + "}";
}

// ---- reading ----

const json::Json& member(const json::Json& object, const char* key, const std::string& where) {
  static const json::Json null;
  if (!object.is_object()) throw Refusal(422, where + ": expected an object, got " + json::describe(object));
  const json::Json* v = json::find(object, key);
  return v != nullptr ? *v : null;
}

std::string text(const json::Json& object, const char* key, const std::string& where, bool required = true) {
  const json::Json& v = member(object, key, where);
  if (v.is_null() && !required) return {};
  if (!v.is_string()) throw Refusal(422, where + ": '" + key + "' must be a string, got " + json::describe(v));
  return v.get<std::string>();
}

double numberOf(const json::Json& object, const char* key, const std::string& where, double fallback) {
  const json::Json& v = member(object, key, where);
  if (v.is_null()) return fallback;
  if (!v.is_number()) throw Refusal(422, where + ": '" + key + "' must be a number, got " + json::describe(v));
  return v.get<double>();
}

const json::Json& array(const json::Json& object, const char* key, const std::string& where) {
  static const json::Json none = json::Json::array();
  const json::Json& v = member(object, key, where);
  if (v.is_null()) return none;
  if (!v.is_array()) throw Refusal(422, where + ": '" + key + "' must be an array, got " + json::describe(v));
  return v;
}

std::vector<std::string> names(const json::Json& object, const char* key, const std::string& where) {
  std::vector<std::string> out;
  for (const json::Json& v : array(object, key, where)) {
    if (!v.is_string()) throw Refusal(422, where + ": '" + key + "' must hold names (strings), got " + json::describe(v));
    out.push_back(v.get<std::string>());
  }
  return out;
}

/// A value of the Project as property text: a string as it is; a number or boolean (a page may
/// send them bare) in the core's text form.
std::string valueText(const json::Json& v, const std::string& where) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number()) return core::DataTypeTraits<double>::print(v.get<double>());
  throw Refusal(422, where + ": expected the value as text (e.g. \"2.5\", \"[0, 0, 1]\"), got " + json::describe(v));
}

deploy::ActivitySpec activityFrom(const json::Json& a, const std::string& component, const std::string& where) {
  deploy::ActivitySpec spec;
  spec.peer_name = component;
  spec.period = numberOf(a, "period", where, 0.0);
  const double priority = numberOf(a, "priority", where, 0.0);
  if (priority != std::floor(priority)) throw Refusal(422, where + ": 'priority' must be an integer, got " + number(priority));
  spec.priority = static_cast<int>(priority);
  const std::string scheduler = text(a, "scheduler", where, false);
  if (!scheduler.empty()) spec.scheduler = scheduler;
  return spec;
}

}  // namespace

deploy::ConnectionSpec connectionFrom(const json::Json& c, const std::string& where) {
  deploy::ConnectionSpec spec;
  spec.output = text(c, "output", where);
  spec.input = text(c, "input", where);
  const std::string at = where + " '" + spec.output + "' -> '" + spec.input + "'";
  const json::Json& policy = member(c, "conn_policy", at);
  if (!policy.is_null()) {
    spec.conn_policy.type = text(policy, "type", at + " conn_policy", false);
    if (spec.conn_policy.type.empty()) spec.conn_policy.type = "data";
    const double size = numberOf(policy, "size", at + " conn_policy", 1.0);
    if (size != std::floor(size)) throw Refusal(422, at + ": conn_policy.size must be an integer, got " + number(size));
    spec.conn_policy.size = static_cast<int>(size);
    spec.conn_policy.transport = text(policy, "transport", at + " conn_policy", false);
    spec.conn_policy.topic = text(policy, "topic", at + " conn_policy", false);
    const json::Json& qos = member(policy, "qos", at + " conn_policy");
    if (!qos.is_null()) {
      if (!qos.is_object()) throw Refusal(422, at + ": conn_policy.qos must be an object, got " + json::describe(qos));
      for (const auto& [k, v] : qos.items()) spec.conn_policy.qos.emplace_back(k, valueText(v, at + " conn_policy.qos." + k));
    }
  }
  return spec;
}

std::string inForceJson(const InForce& now) {
  std::string out = "{\"t\":" + number(now.t) + ",\"switches\":" + std::to_string(now.switches) + ",\"deployments\":[";
  for (std::size_t i = 0; i < now.deployments.size(); ++i)
    out += std::string(i ? "," : "") + "{\"scope\":" + json::quoted(now.deployments[i].first) +
           ",\"deployment\":" + json::quoted(now.deployments[i].second) + "}";
  out += "],\"configuration\":" + json::quoted(now.configuration) + ",\"running\":" + stringArray(now.running) +
         ",\"connections\":[";
  for (std::size_t i = 0; i < now.connections.size(); ++i) out += (i ? "," : "") + connectionJson(now.connections[i]);
  return out + "]}";
}

std::string projectJson(const deploy::DeploymentDescription& d, const Layout& layout) {
  std::string out = "{\"packages\":" + stringArray(d.packages) + ",\"components\":[";
  for (std::size_t i = 0; i < d.components.size(); ++i) {
    const deploy::ComponentSpec& c = d.components[i];
    out += std::string(i ? "," : "") + "{\"name\":" + json::quoted(c.peer_name) + ",\"type\":" + json::quoted(c.component_type);
    // Without a position in the layout: none, the page lays the block out (it knows each block's
    // height from its ports, so no two overlap).
    if (const auto at = layout.find(c.peer_name); at != layout.end())
      out += ",\"x\":" + number(at->second.first) + ",\"y\":" + number(at->second.second);
    out += ",\"properties\":{";
    bool first = true;
    for (const deploy::PropertyValueDescription& p : d.properties) {
      if (p.component != c.peer_name) continue;
      out += (first ? "" : ",") + json::quoted(p.property) + ":" + json::quoted(p.value);
      first = false;
    }
    out += "},\"activity\":";
    const deploy::ActivitySpec* activity = nullptr;
    for (const deploy::ActivitySpec& a : d.activities)
      if (a.peer_name == c.peer_name) activity = &a;
    out += activity != nullptr ? activityJson(*activity) : "null";
    out += "}";
  }
  out += "],\"peers\":[";
  for (std::size_t i = 0; i < d.peers.size(); ++i)
    out += std::string(i ? "," : "") + "{\"component\":" + json::quoted(d.peers[i].peer_name) +
           ",\"peers\":" + stringArray(d.peers[i].peers_to_add) + "}";
  out += "],\"connections\":[";
  for (std::size_t i = 0; i < d.connections.size(); ++i) out += (i ? "," : "") + connectionJson(d.connections[i]);
  out += "],\"deployments\":[";
  for (std::size_t i = 0; i < d.deployments.size(); ++i) {
    const deploy::DeploymentSpec& s = d.deployments[i];
    std::vector<std::string> components;
    for (const deploy::NameEntry& c : s.components) components.push_back(c.name);
    out += std::string(i ? "," : "") + "{\"name\":" + json::quoted(s.name) + ",\"scope\":" + json::quoted(s.scope) +
           ",\"components\":" + stringArray(components) + ",\"activities\":[";
    for (std::size_t k = 0; k < s.activities.size(); ++k) {
      std::string a = activityJson(s.activities[k]);
      out += (k ? "," : "") + ("{\"component\":" + json::quoted(s.activities[k].peer_name) + "," + a.substr(1));
    }
    out += "],\"connections\":[";
    for (std::size_t k = 0; k < s.connections.size(); ++k) out += (k ? "," : "") + connectionJson(s.connections[k]);
    out += "]}";
  }
  out += "],\"configurations\":[";
  for (std::size_t i = 0; i < d.configurations.size(); ++i) {
    const deploy::ConfigurationSpec& c = d.configurations[i];
    out += std::string(i ? "," : "") + "{\"name\":" + json::quoted(c.name) + ",\"values\":{";
    for (std::size_t k = 0; k < c.values.size(); ++k)
      out += (k ? "," : "") + json::quoted(c.values[k].component + "." + c.values[k].property) + ":" + json::quoted(c.values[k].value);
    out += "}}";
  }
  out += "],\"configure\":" + stringArray(d.configure) + ",\"start\":" + stringArray(d.start) +
         ",\"apply\":" + stringArray(d.apply) + ",\"configuration\":" + json::quoted(d.configuration) + "}";
  return out;
}

deploy::DeploymentDescription fromProjectJson(const json::Json& project, const Palette& palette, Layout& layout) {
  deploy::DeploymentDescription d;
  const std::string at = "project";
  d.packages = names(project, "packages", at);
  std::set<std::string> seen;
  for (const json::Json& c : array(project, "components", at)) {
    const std::string name = text(c, "name", at + ".components[]");
    const std::string where = "component '" + name + "'";
    if (!seen.insert(name).second) throw Refusal(422, where + ": two components have this name");
    const std::string type = text(c, "type", where);
    d.components.push_back({name, type, {}});
    layout[name] = {numberOf(c, "x", where, 0.0), numberOf(c, "y", where, 0.0)};
    const PaletteType* t = palette.find(type);
    const json::Json& properties = member(c, "properties", where);
    if (!properties.is_null() && !properties.is_object())
      throw Refusal(422, where + ": 'properties' must be an object { name: text }, got " + json::describe(properties));
    for (const auto& [property, value] : properties.items()) {
      const std::string value_at = where + " property '" + property + "'";
      const std::string value_text = valueText(value, value_at);
      const core::PropertyInfo* info = t != nullptr ? t->property(property) : nullptr;
      if (info != nullptr && info->value == value_text) continue;  // the default: not written
      d.properties.push_back({name, property, info != nullptr ? info->type : "string", value_text});
    }
    const json::Json& activity = member(c, "activity", where);
    if (!activity.is_null()) d.activities.push_back(activityFrom(activity, name, where + " activity"));
  }
  for (const json::Json& p : array(project, "peers", at)) {
    const std::string component = text(p, "component", at + ".peers[]");
    d.peers.push_back({component, names(p, "peers", "peers of '" + component + "'"), {}});
  }
  for (const json::Json& c : array(project, "connections", at)) d.connections.push_back(connectionFrom(c, "connection"));
  for (const json::Json& s : array(project, "deployments", at)) {
    deploy::DeploymentSpec spec;
    spec.name = text(s, "name", at + ".deployments[]");
    const std::string where = "deployment '" + spec.name + "'";
    spec.scope = text(s, "scope", where, false);
    for (const std::string& c : names(s, "components", where)) spec.components.push_back({c, {}});
    for (const json::Json& a : array(s, "activities", where)) {
      const std::string component = text(a, "component", where + " activities[]");
      spec.activities.push_back(activityFrom(a, component, where + " activity of '" + component + "'"));
    }
    for (const json::Json& c : array(s, "connections", where)) spec.connections.push_back(connectionFrom(c, where + " connection"));
    d.deployments.push_back(std::move(spec));
  }
  for (const json::Json& c : array(project, "configurations", at)) {
    deploy::ConfigurationSpec spec;
    spec.name = text(c, "name", at + ".configurations[]");
    const std::string where = "configuration '" + spec.name + "'";
    const json::Json& values = member(c, "values", where);
    if (!values.is_null() && !values.is_object())
      throw Refusal(422, where + ": 'values' must be an object { \"Component.property\": text }, got " + json::describe(values));
    for (const auto& [path, value] : values.items()) {
      const auto dot = path.find('.');
      if (dot == std::string::npos || dot == 0 || dot + 1 == path.size())
        throw Refusal(422, where + ": '" + path + "' must be Component.property");
      spec.values.push_back({path.substr(0, dot), path.substr(dot + 1), valueText(value, where + " value '" + path + "'"), {}});
    }
    d.configurations.push_back(std::move(spec));
  }
  d.configure = names(project, "configure", at);
  d.start = names(project, "start", at);
  d.apply = names(project, "apply", at);
  d.configuration = text(project, "configuration", at, false);
  return d;
}

std::string layoutJson(const Layout& layout) {
  std::string out = "{\"components\":{";
  bool first = true;
  for (const auto& [name, xy] : layout) {
    out += (first ? "" : ",") + json::quoted(name) + ":{\"x\":" + number(xy.first) + ",\"y\":" + number(xy.second) + "}";
    first = false;
  }
  return out + "}}\n";
}

Layout parseLayout(const std::string& text) {
  Layout layout;
  try {
    const json::Json v = json::parse(text);
    const json::Json* components = json::find(v, "components");
    if (components == nullptr || !components->is_object()) return layout;
    for (const auto& [name, xy] : components->items()) {
      const json::Json* x = json::find(xy, "x");
      const json::Json* y = json::find(xy, "y");
      if (x != nullptr && y != nullptr && x->is_number() && y->is_number()) layout[name] = {x->get<double>(), y->get<double>()};
    }
  } catch (const std::exception&) {
    // A sidecar that does not parse only loses the positions: the blocks go on the grid.
  }
  return layout;
}

}  // namespace cobra::studio::editor
