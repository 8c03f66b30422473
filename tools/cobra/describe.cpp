#include "describe.hpp"

#include <sstream>

namespace cobra::tools {
namespace {

std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string policyTable(const core::ConnPolicy& policy) {
  std::string table;
  switch (policy.kind) {
    case core::ConnPolicy::Kind::Data: table = "{ type = \"data\""; break;
    case core::ConnPolicy::Kind::Buffer: table = "{ type = \"buffer\", size = " + std::to_string(policy.size); break;
    case core::ConnPolicy::Kind::Circular: table = "{ type = \"circular\", size = " + std::to_string(policy.size); break;
  }
  // A transport's connection: its name, topic and settings (DDS: the qos), values as the text
  // the transport parsed, which it parses again the same.
  if (!policy.transport.empty()) table += ", transport = " + quoted(policy.transport);
  if (!policy.topic.empty()) table += ", topic = " + quoted(policy.topic);
  if (!policy.options.empty()) {
    table += ", qos = {";
    for (const auto& [key, value] : policy.options) table += " " + key + " = " + quoted(value) + ",";
    table.back() = ' ';
    table += "}";
  }
  return table + " }";
}

}  // namespace

std::string describeDeployment(const deploy::Configurator& configurator, const std::string& origin) {
  const core::ComponentRegistry& registry = configurator.getReferences();
  std::ostringstream lua;
  lua << "-- Described from " << origin << " by `cobra describe`: the deployment as Configurator tables.\n\n";
  lua << "packages_list = {\n";
  for (const std::string& package : configurator.packages().loadedPackages())
    lua << "  " << quoted(package) << ",\n";
  lua << "}\n\ncomponents_list = {\n";
  for (const core::Component* c : registry.components())
    lua << "  { peer_name = " << quoted(c->name()) << ", component_type = " << quoted(configurator.componentTypeOf(c->name()))
        << " },  -- " << core::toString(c->role()) << ", " << core::toString(c->state()) << "\n";
  lua << "}\n\nactivities_list = {\n";
  for (const core::Component* c : registry.components()) {
    const deploy::ActivitySpec* a = configurator.activityOf(c->name());
    if (a == nullptr) continue;
    std::ostringstream period;
    period << a->period;
    lua << "  { peer_name = " << quoted(c->name()) << ", period = " << period.str() << ", priority = " << a->priority
        << ", scheduler = " << quoted(a->scheduler) << " },\n";
  }
  lua << "}\n\npeers_list = {\n";
  for (const core::Component* c : registry.components()) {
    const auto& peers = configurator.peersOf(c->name());
    if (peers.empty()) continue;
    lua << "  { peer_name = " << quoted(c->name()) << ", peers_to_add = {";
    for (std::size_t i = 0; i < peers.size(); ++i) lua << (i ? ", " : " ") << quoted(peers[i]);
    lua << " } },\n";
  }
  lua << "}\n\nconnections_list = {\n";
  int outside = 0;
  for (const core::Component* c : registry.components())
    for (const core::PortBase* port : c->ports()) {
      if (port->direction() != core::PortDirection::Output) continue;
      for (const auto& channel : port->connections()) {
        // A transport's connection with both ends here: its reader is the far end's port (the
        // channel's own reader is the transport end's hidden port).
        const core::PortBase& reader = channel->peer() != nullptr ? *channel->peer() : channel->reader();
        if (reader.owner() == nullptr || registry.find(reader.owner()->name()) != reader.owner()) {
          ++outside;
          continue;
        }
        lua << "  { output = " << quoted(port->fullName()) << ", input = " << quoted(reader.fullName())
            << ", conn_policy = " << policyTable(channel->policy()) << " },\n";
      }
    }
  lua << "}\n";
  if (outside > 0) lua << "-- " << outside << " connection(s) to ports outside the deployment are not listed.\n";
  lua << "\ninitConfigurator(packages_list, components_list)\nsetActivities(activities_list)\naddPeers(peers_list)\n"
      << "connectPorts(connections_list)\n";
  std::string configure = "{", start = "{";
  for (const core::Component* c : registry.components()) {
    if (c->state() == core::State::Stopped || c->state() == core::State::Running) configure += " " + quoted(c->name()) + ",";
    if (c->state() == core::State::Running) start += " " + quoted(c->name()) + ",";
  }
  lua << "configureComponents(" << configure << " })\nstartComponents(" << start << " })\n";
  return lua.str();
}

}  // namespace cobra::tools
