#include "cobra/deploy/lint.hpp"

namespace cobra::deploy {
namespace {

using core::DataKind;
using core::Role;

std::string kindText(const core::PortBase& port) {
  return std::string(port.type().name) + " is " + std::string(core::toString(port.type().kind));
}

bool readsKind(const core::Component& component, DataKind kind) {
  for (const core::PortBase* port : component.ports())
    if (port->direction() == core::PortDirection::Input && port->type().kind == kind) return true;
  return false;
}

bool hasInputs(const core::Component& component) {
  for (const core::PortBase* port : component.ports())
    if (port->direction() == core::PortDirection::Input) return true;
  return false;
}

/// The reader-side rule `input`'s owner breaks by reading `kind`, or "".
std::string readerRule(Role role, DataKind kind) {
  switch (role) {
    case Role::Calculation:
      return kind == DataKind::Pure ? "" : "a Calculation component may read only pure data";
    case Role::Decision:
      return kind == DataKind::Pure ? "" : "a Decision component may read only pure data";
    case Role::Supervision:
      return kind == DataKind::Logic ? "" : "a Supervision component may read only logic data";
    case Role::Bridge:
      return "";
  }
  return "";
}

/// The writer-side rule `output`'s owner breaks, or "".
std::string writerRule(const core::PortBase& output) {
  const core::Component& owner = *output.owner();
  const DataKind kind = output.type().kind;
  if (owner.findPort("events") == &output) return "";  // events about its own behaviour
  switch (owner.role()) {
    case Role::Calculation:
      return kind == DataKind::Pure ? ""
                                    : "a Calculation component may write only pure data (and events about its "
                                      "own behaviour on its 'events' port)";
    case Role::Supervision:
      return kind == DataKind::Logic ? "" : "a Supervision component may write only logic data";
    case Role::Decision:
      return kind == DataKind::Logic ? "" : "a Decision component may write only logic data";
    case Role::Bridge:
      if (!hasInputs(owner) || readsKind(owner, kind)) return "";
      return std::string("a Bridge component writes the same kind of data it reads, and ") + owner.name() +
             " reads only " + std::string(core::toString(kind == DataKind::Pure ? DataKind::Logic : DataKind::Pure));
  }
  return "";
}

}  // namespace

std::vector<LintViolation> lintConnection(const core::PortBase& output, const core::PortBase& input,
                                          const SourceLocation& where) {
  std::vector<LintViolation> out;
  if (output.owner() == nullptr || input.owner() == nullptr) return out;
  const Role writer = output.owner()->role();
  const Role reader = input.owner()->role();
  const std::string head = (where == SourceLocation{} ? std::string() : where.text() + ": ") + output.fullName() + " (" +
                           std::string(core::toString(writer)) + ") -> " + input.fullName() + " (" +
                           std::string(core::toString(reader)) + "): ";
  auto report = [&](const std::string& rule) {
    out.push_back({output.fullName(), input.fullName(), writer, reader, rule, where,
                   head + rule + ", but " + kindText(output)});
  };
  if (const std::string rule = writerRule(output); !rule.empty()) report(rule);
  if (const std::string rule = readerRule(reader, input.type().kind); !rule.empty()) report(rule);
  return out;
}

std::vector<LintViolation> lint(const std::vector<ConnectionSpec>& connections,
                                const core::ComponentRegistry& components) {
  return lint(connections, [&components](std::string_view name) -> const core::Component* { return components.find(name); });
}

std::vector<LintViolation> lint(const std::vector<ConnectionSpec>& connections, const ComponentLookup& find) {
  std::vector<LintViolation> out;
  for (const ConnectionSpec& spec : connections) {
    const auto dot_out = spec.output.find('.');
    const auto dot_in = spec.input.find('.');
    if (dot_out == std::string::npos || dot_in == std::string::npos) continue;
    const core::Component* writer = find(std::string_view(spec.output).substr(0, dot_out));
    const core::Component* reader = find(std::string_view(spec.input).substr(0, dot_in));
    if (writer == nullptr || reader == nullptr) continue;
    const core::PortBase* output = writer->findPort(spec.output.substr(dot_out + 1));
    const core::PortBase* input = reader->findPort(spec.input.substr(dot_in + 1));
    if (output == nullptr || input == nullptr) continue;
    for (auto& violation : lintConnection(*output, *input, spec.where)) out.push_back(std::move(violation));
  }
  return out;
}

std::string toText(const std::vector<LintViolation>& violations) {
  std::string text;
  for (const auto& v : violations) text += (text.empty() ? "" : "\n") + v.message;
  return text;
}

}  // namespace cobra::deploy
