// The one writer of deployment descriptions as Lua deployment files (description.hpp).

#include <cctype>
#include <charconv>
#include <chrono>
#include <map>
#include <sstream>

#include "cobra/core/data_type.hpp"
#include "cobra/core/error.hpp"
#include "cobra/core/event.hpp"
#include "cobra/deploy/description.hpp"

namespace cobra::deploy {
namespace {

/// Shortest text that reads back to the same double (periods: 0.001 stays "0.001").
std::string number(double value) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return ec == std::errc() ? std::string(buffer, end) : std::string("0");
}

bool isIdentifier(std::string_view s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (const char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

/// `name` as a Lua table key: `name` or `["name"]`.
std::string key(std::string_view name) { return isIdentifier(name) ? std::string(name) : "[" + luaString(name) + "]"; }

std::string trim(std::string_view text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) text.remove_prefix(1);
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
  return std::string(text);
}

/// A Lua number literal for `text` (a number as the core prints it), or "" when it is none.
/// Lua has no literal for infinity or NaN: math.huge, and a NaN of the sign the text gives
/// (0/0 has the sign the machine gives it; math.abs clears it).
std::string luaNumber(std::string_view text) {
  const std::string t = trim(text);
  if (t == "inf" || t == "+inf") return "math.huge";
  if (t == "-inf") return "-math.huge";
  if (t == "nan" || t == "+nan") return "math.abs(0/0)";
  if (t == "-nan") return "-math.abs(0/0)";
  double value = 0.0;
  const char* first = t.data() + (!t.empty() && t[0] == '+' ? 1 : 0);
  const auto [end, ec] = std::from_chars(first, t.data() + t.size(), value);
  if (t.empty() || ec != std::errc() || end != t.data() + t.size()) return {};
  return std::string(first, end);
}

/// The types written as a Lua array of numbers (script/convert.hpp reads each from one), with
/// their number of elements (0: any).
struct ListForm {
  std::string_view type;
  std::size_t count;
  std::string_view what;
};
constexpr ListForm kListForms[] = {
    {"vector<double>", 0, "[a, b, ...]"},
    {"KDL.JntArray", 0, "[q1, q2, ...] (joint values)"},
    {"KDL.Vector", 3, "[x, y, z] (m)"},
    {"KDL.Rotation", 4, "[qx, qy, qz, qw] (a unit quaternion)"},
    {"KDL.Frame", 7, "[x, y, z, qx, qy, qz, qw] (m, a unit quaternion)"},
    {"KDL.Twist", 6, "[vx, vy, vz, wx, wy, wz] (m/s, rad/s)"},
    {"KDL.Wrench", 6, "[fx, fy, fz, tx, ty, tz] (N, N m)"},
};

const ListForm* listForm(std::string_view type) {
  for (const ListForm& form : kListForms)
    if (form.type == type) return &form;
  return nullptr;
}

/// `text` (a list as the core prints it: "[1, 2.5]", brackets optional) as a Lua array.
std::string luaList(const ListForm& form, std::string_view text) {
  const std::string type(form.type);
  std::string t = trim(text);
  if (!t.empty() && t.front() == '[') {
    if (t.back() != ']') throw core::Error("expected a list " + std::string(form.what) + " for a " + type + ", got '" + t + "'");
    t = trim(std::string_view(t).substr(1, t.size() - 2));
  }
  std::string out = "{";
  std::size_t i = 0, count = 0;
  while (i < t.size()) {
    std::size_t end = t.find_first_of(", \t", i);
    if (end == std::string::npos) end = t.size();
    const std::string literal = luaNumber(std::string_view(t).substr(i, end - i));
    if (literal.empty()) throw core::Error("expected a list of numbers for a " + type + ", got '" + std::string(text) + "'");
    out += (count++ ? ", " : " ") + literal;
    i = t.find_first_not_of(", \t", end);
    if (i == std::string::npos) break;
  }
  if (form.count != 0 && count != form.count)
    throw core::Error("expected " + std::to_string(form.count) + " numbers " + std::string(form.what) + " for a " + type +
                      ", got " + std::to_string(count) + ": '" + std::string(text) + "'");
  return out + (count ? " }" : "}");
}

std::string nameList(const std::vector<std::string>& names) {
  std::string out = "{";
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", " : " ") + luaString(names[i]);
  return out + (names.empty() ? "}" : " }");
}

std::string activityEntry(const ActivitySpec& a) {
  return "{ peer_name = " + luaString(a.peer_name) + ", period = " + number(a.period) +
         ", priority = " + std::to_string(a.priority) + ", scheduler = " + luaString(a.scheduler) +
         (a.own_pace ? ", own_pace = true" : "") + (a.max_age > 0.0 ? ", max_age = " + number(a.max_age) : std::string()) + " }";
}

std::string connectionEntry(const ConnectionSpec& c) {
  return "{ output = " + luaString(c.output) + ", input = " + luaString(c.input) +
         ", conn_policy = " + luaPolicyTable(c.conn_policy) + " }";
}

template <class T, class F>
void writeList(std::ostringstream& lua, const std::string& indent, const std::vector<T>& items, F entry) {
  for (const T& item : items) lua << indent << "  " << entry(item) << ",\n";
}

}  // namespace

std::string luaString(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default: out += c;
    }
  }
  return out + "\"";
}

std::string luaValue(std::string_view type, std::string_view text) {
  if (type == "double") {
    const std::string literal = luaNumber(text);
    if (literal.empty()) throw core::Error("expected a number for a double, got '" + std::string(text) + "'");
    return literal;
  }
  if (type == "int") {
    // Lua reads an int from an integral number only (script/convert.hpp): 1.5 would not load.
    const std::string t = trim(text);
    int value = 0;
    const char* first = t.data() + (!t.empty() && t[0] == '+' ? 1 : 0);
    const auto [end, ec] = std::from_chars(first, t.data() + t.size(), value);
    if (t.empty() || ec != std::errc() || end != t.data() + t.size())
      throw core::Error("expected an integer for an int (-2147483648 to 2147483647), got '" + std::string(text) + "'");
    return std::to_string(value);
  }
  if (type == "bool") {
    const std::string t = trim(text);
    if (t != "true" && t != "false") throw core::Error("expected true or false, got '" + std::string(text) + "'");
    return t;
  }
  if (const ListForm* form = listForm(type)) return luaList(*form, text);
  if (type == "Event") {
    // The core prints "e_done from Planner at 1.5 s"; Lua reads a bare string as the name only.
    core::Event event;
    if (!core::DataTypeTraits<core::Event>::parse(text, event))
      throw core::Error("expected an event (" + std::string(core::DataTypeTraits<core::Event>::format) + ") for an Event, got '" +
                        std::string(text) + "'");
    const double stamp = std::chrono::duration<double>(event.stamp).count();
    if (event.source.empty() && stamp == 0.0) return luaString(event.name.view());
    return "{ name = " + luaString(event.name.view()) +
           (event.source.empty() ? std::string() : ", source = " + luaString(event.source.view())) +
           ", stamp = " + core::DataTypeTraits<double>::print(stamp) + " }";
  }
  // A string is itself; every other registered type (a TaskState, a package's own) Lua sets from
  // its text form, a string (Property::setFromText parses it). A type this process has not
  // registered has no form at all.
  if (type != "string" && core::TypeRegistry::find(type) == nullptr)
    throw core::Error("type '" + std::string(type) + "' has no Lua form: no type of that name is registered "
                      "(a type of a package that is not loaded?)");
  return luaString(text);
}

std::string luaPolicyTable(const ConnPolicySpec& spec) {
  // The seam of the transports (DDS between hosts): a policy naming one writes it, its topic and
  // QoS.
  std::string out = "{ type = " + luaString(spec.type);
  if (spec.type != "data") out += ", size = " + std::to_string(spec.size);
  if (!spec.transport.empty()) out += ", transport = " + luaString(spec.transport);
  if (!spec.topic.empty()) out += ", topic = " + luaString(spec.topic);
  if (!spec.qos.empty()) {
    out += ", qos = {";
    for (std::size_t i = 0; i < spec.qos.size(); ++i)
      out += (i ? ", " : " ") + key(spec.qos[i].first) + " = " + luaString(spec.qos[i].second);
    out += " }";
  }
  return out + " }";
}


std::string toLua(const DeploymentDescription& d) {
  std::ostringstream lua;
  lua << "-- A deployment as Configurator tables (thesis §3.2.2), written by cobra (`cobra describe`, `cobra edit`).\n\n";
  lua << "packages_list = {\n";
  for (const std::string& package : d.packages) lua << "  " << luaString(package) << ",\n";
  lua << "}\n\ncomponents_list = {\n";
  writeList(lua, "", d.components, [](const ComponentSpec& c) {
    return "{ peer_name = " + luaString(c.peer_name) + ", component_type = " + luaString(c.component_type) + " }";
  });
  lua << "}\n\nactivities_list = {\n";
  writeList(lua, "", d.activities, activityEntry);
  lua << "}\n\npeers_list = {\n";
  writeList(lua, "", d.peers, [](const PeerSpec& p) {
    return "{ peer_name = " + luaString(p.peer_name) + ", peers_to_add = " + nameList(p.peers_to_add) + " }";
  });
  lua << "}\n\nconnections_list = {\n";
  writeList(lua, "", d.connections, connectionEntry);
  lua << "}\n";
  if (d.outside_connections > 0)
    lua << "-- " << d.outside_connections << " connection(s) to ports outside the deployment are not listed.\n";

  lua << "\ninitConfigurator(packages_list, components_list)\n";
  if (!d.properties.empty()) {
    lua << "getReferences()\n";
    for (const PropertyValueDescription& p : d.properties) {
      const std::string target = isIdentifier(p.component) ? p.component : "_G[" + luaString(p.component) + "]";
      std::string value;
      try {
        value = luaValue(p.type, p.value);
      } catch (const core::Error& e) {
        throw core::Error("component '" + p.component + "': property '" + p.property + "': " + e.what());
      }
      lua << target << (isIdentifier(p.property) ? "." + p.property : "[" + luaString(p.property) + "]") << " = "
          << value << "\n";
    }
  }
  // Configured before they are connected: a component may make ports when it configures (a
  // trajectory generator's desCartPose_i, one per arm), and the connections may name them.
  lua << "setActivities(activities_list)\naddPeers(peers_list)\nconfigureComponents(" << nameList(d.configure)
      << ")\nconnectPorts(connections_list)\n";
  if (d.executor.declared) {
    const ExecutorSpec& e = d.executor;
    lua << "setExecutor({ period = " << number(e.period) << ", priority = " << e.priority
        << ", scheduler = " << luaString(e.scheduler) << ", cpu = " << e.cpu
        << ", lock_memory = " << (e.lock_memory ? "true" : "false") << ", on_deadline_miss = " << luaString(e.on_deadline_miss)
        << ", safe_stop_after = " << e.safe_stop_after << " })\n";
  }

  for (const DeploymentSpec& deployment : d.deployments) {
    lua << "\ndefineDeployment(" << luaString(deployment.name) << ", {\n";
    if (!deployment.scope.empty()) lua << "  scope = " << luaString(deployment.scope) << ",\n";
    std::vector<std::string> names;
    for (const NameEntry& c : deployment.components) names.push_back(c.name);
    lua << "  components = " << nameList(names) << ",\n  activities = {\n";
    writeList(lua, "  ", deployment.activities, activityEntry);
    lua << "  },\n  connections = {\n";
    writeList(lua, "  ", deployment.connections, connectionEntry);
    lua << "  },\n})\n";
  }
  for (const ConfigurationSpec& configuration : d.configurations) {
    // Grouped by component and sorted, as a Lua table comes back (lua_configuration.hpp); the
    // values stay text, so nothing is reformatted on the way.
    std::map<std::string, std::map<std::string, std::string>> by_component;
    for (const PropertyValueSpec& v : configuration.values) by_component[v.component][v.property] = v.value;
    lua << "\ndefineConfiguration(" << luaString(configuration.name) << ", {\n";
    for (const auto& [component, values] : by_component) {
      lua << "  " << key(component) << " = {";
      bool first = true;
      for (const auto& [property, value] : values) {
        lua << (first ? " " : ", ") << key(property) << " = " << luaString(value);
        first = false;
      }
      lua << " },\n";
    }
    lua << "})\n";
  }
  lua << "\nstartComponents(" << nameList(d.start) << ")\n";
  for (const std::string& name : d.apply) lua << "applyDeployment(" << luaString(name) << ")\n";
  if (!d.configuration.empty()) lua << "applyConfiguration(" << luaString(d.configuration) << ")\n";
  return lua.str();
}

}  // namespace cobra::deploy
