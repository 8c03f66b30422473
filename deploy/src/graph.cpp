#include "cobra/deploy/graph.hpp"

#include <cctype>
#include <set>
#include <sstream>

namespace cobra::deploy {
namespace {

/// DOT record labels treat these characters as structure; escape them in names and types.
std::string escapeRecord(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '{' || c == '}' || c == '|' || c == '<' || c == '>' || c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

/// Port identifiers inside a record: "p_<name>", every character other than a letter, a digit or
/// '_' written as "_xx" (its hex code): a Reporter's reader ports are named "Comp:port", and ':'
/// separates a node from its port in DOT.
std::string portId(const std::string& port) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string id = "p_";
  for (const char c : port) {
    if (std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_') {
      id += c;
    } else {
      const auto byte = static_cast<unsigned char>(c);
      id += {'_', kHex[byte >> 4], kHex[byte & 0xF]};
    }
  }
  return id;
}

}  // namespace

std::string roleColour(core::Role role) {
  switch (role) {
    case core::Role::Calculation: return "#9ecae1";
    case core::Role::Supervision: return "#fdae6b";
    case core::Role::Decision: return "#a1d99b";
    case core::Role::Bridge: return "#d9d9d9";
  }
  return "#ffffff";
}

std::string graphvizDot(const core::ComponentRegistry& registry, const std::string& title) {
  std::ostringstream dot;
  dot << "digraph " << quoted(title) << " {\n"
      << "  rankdir=LR;\n  node [shape=record, style=filled, fontname=\"Helvetica\", fontsize=10];\n"
      << "  edge [fontname=\"Helvetica\", fontsize=9];\n";
  std::set<const core::Component*> members;
  for (const core::Component* c : registry.components()) members.insert(c);

  for (const core::Component* c : registry.components()) {
    std::string inputs, outputs;
    for (const core::PortBase* p : c->ports()) {
      std::string& side = p->direction() == core::PortDirection::Input ? inputs : outputs;
      if (!side.empty()) side += "|";
      side += "<" + portId(p->name()) + "> " + escapeRecord(p->name()) + " : " + escapeRecord(std::string(p->type().name));
    }
    dot << "  " << quoted(c->name()) << " [fillcolor=" << quoted(roleColour(c->role())) << ", label=\"{{"
        << (inputs.empty() ? " " : inputs) << "}|{" << escapeRecord(c->name()) << "\\n("
        << core::toString(c->role()) << ", " << core::toString(c->state()) << ")}|{"
        << (outputs.empty() ? " " : outputs) << "}}\"];\n";
  }

  std::set<std::string> outsiders;
  for (const core::Component* c : registry.components()) {
    for (const core::PortBase* p : c->ports()) {
      if (p->direction() != core::PortDirection::Output) continue;
      for (const auto& channel : p->connections()) {
        const core::PortBase& reader = channel->reader();
        std::string target;
        if (reader.owner() != nullptr && members.count(reader.owner()) != 0) {
          target = quoted(reader.owner()->name()) + ":" + portId(reader.name()) + ":w";
        } else {
          outsiders.insert(reader.fullName());
          target = quoted(reader.fullName());
        }
        dot << "  " << quoted(c->name()) << ":" << portId(p->name()) << ":e -> " << target
            << " [label=" << quoted(channel->policy().describe())
            << (p->type().kind == core::DataKind::Logic ? ", style=dashed" : "") << "];\n";
      }
    }
  }
  for (const std::string& name : outsiders) dot << "  " << quoted(name) << " [shape=plaintext, style=\"\"];\n";
  dot << "}\n";
  return dot.str();
}

}  // namespace cobra::deploy
