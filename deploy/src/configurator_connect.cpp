#include <algorithm>
#include <iterator>
#include <set>

#include "cobra/core/transport.hpp"
#include "cobra/deploy/configurator.hpp"
#include "cobra/deploy/description.hpp"
#include "undo_journal.hpp"

namespace cobra::deploy {

Configurator::ResolvedConnection Configurator::resolve(const ConnectionSpec& spec) const {
  core::PortBase& output = port(spec.output, spec.where);
  core::PortBase& input = port(spec.input, spec.where);
  return {&output, &input, toConnPolicy(spec.conn_policy, spec.where), &spec};
}

void Configurator::checkConnection(const ResolvedConnection& c) const {
  const std::string head = c.spec->where.text() + ": ";
  try {
    // The checks core::connectPorts makes, without connecting: direction, duplicate, capacity...
    core::checkConnectable(*c.output, *c.input);
    // ...and the type, which core checks with the port's static type when it connects.
    if (c.output->type().id != c.input->type().id)
      core::throwConnectionError(*c.output, *c.input,
                                 "the types differ (" + std::string(c.output->type().name) + " vs " +
                                     std::string(c.input->type().name) + "); connect ports of the same type");
  } catch (const core::Error& e) {
    throw core::Error(head + e.what());
  }
}

std::vector<LintViolation> Configurator::checkRoles(const std::vector<ConnectionSpec>& connections) {
  std::vector<LintViolation> violations = placement_ ? lintOnThisHost(connections) : lint(connections, components_);
  if (violations.empty()) return violations;
  if (options_.strict_roles)
    throw core::Error(std::to_string(violations.size()) + " role rule violation" +
                      (violations.size() == 1 ? "" : "s") + " (strict mode refuses them):\n" + toText(violations));
  for (const LintViolation& v : violations) warnings_.push_back("role rule: " + v.message);
  return violations;
}

std::vector<LintViolation> Configurator::lintOnThisHost(const std::vector<ConnectionSpec>& connections) const {
  // A connection to another host is linted with the shadow of its far end, which has that
  // component's ports and role: the rules do not change with where a component runs. Each host
  // lints the connections it makes an end of; remote -> remote, and an everywhere component's
  // connection to a remote one, are the other host's (connectAcrossHosts makes nothing for them).
  const auto find = [this](std::string_view name) -> const core::Component* {
    const core::Component* local = components_.find(name);
    return local != nullptr ? local : remote_.find(name);
  };
  const auto componentOf = [](const std::string& port) { return port.substr(0, port.find('.')); };
  std::vector<LintViolation> violations;
  for (const ConnectionSpec& spec : connections) {
    const std::string writer = componentOf(spec.output), reader = componentOf(spec.input);
    const bool writer_remote = isRemote(writer), reader_remote = isRemote(reader);
    const auto local = [&](const std::string& name) {
      return components_.find(name) != nullptr && placement_->siteOf(name, spec.where) == Placement::Site::Local;
    };
    if ((writer_remote && !local(reader)) || (reader_remote && !local(writer))) continue;
    for (LintViolation& v : lint({spec}, find)) {
      if (writer_remote || reader_remote)
        v.message += " (the connection crosses hosts: host '" + placement_->hostOf(writer, spec.where) + "' -> host '" +
                     placement_->hostOf(reader, spec.where) + "')";
      violations.push_back(std::move(v));
    }
  }
  return violations;
}

std::vector<LintViolation> Configurator::connectPorts(const std::vector<ConnectionSpec>& connections_list) {
  const std::lock_guard lock(mutex_);
  std::vector<ResolvedConnection> resolved;
  resolved.reserve(connections_list.size());
  std::set<std::pair<const core::PortBase*, const core::PortBase*>> in_list;
  for (const ConnectionSpec& spec : connections_list) {
    ResolvedConnection c = resolve(spec);
    checkConnection(c);
    if (!in_list.emplace(c.output, c.input).second)
      throw core::Error(spec.where.text() + ": " + spec.output + " -> " + spec.input +
                        " appears twice in this list; connect two ports once");
    resolved.push_back(c);
  }
  std::vector<LintViolation> violations;
  try {
    violations = checkRoles(connections_list);
  } catch (const std::exception& e) {
    throw core::Error(std::string("connectPorts: nothing was connected: ") + e.what());
  }

  detail::UndoJournal journal;
  for (const ResolvedConnection& c : resolved) {
    if (placement_ && (isRemote(c.output->owner()->name()) || isRemote(c.input->owner()->name()))) {
      connectAcrossHosts(c, journal);
      continue;
    }
    try {
      core::connectPorts(*c.output, *c.input, c.policy);
    } catch (const std::exception& e) {
      journal.fail(c.spec->where.text() + ": " + e.what());
    }
    connections_.push_back({c.spec->output, c.spec->input, c.policy, c.spec->where, false, {}});
    journal.record("the connection " + c.spec->output + " -> " + c.spec->input, [this, c] {
      core::disconnectPorts(*c.output, *c.input);
      std::erase_if(connections_, [&](const Connection& made) {
        return made.output == c.spec->output && made.input == c.spec->input;
      });
    });
  }
  return violations;
}

std::vector<ConnectionSpec> Configurator::madeConnections() const {
  std::lock_guard lock(mutex_);
  std::vector<ConnectionSpec> made;
  for (const Connection& c : connections_)
    if (!c.from_deployment) made.push_back({c.output, c.input, connPolicySpecOf(c.policy), c.where});
  return made;
}

void Configurator::connectAcrossHosts(const ResolvedConnection& c, detail::UndoJournal& journal) {
  const SourceLocation& where = c.spec->where;
  const auto site = [&](const core::PortBase* p) { return placement_->siteOf(p->owner()->name(), where); };
  const Placement::Site out = site(c.output), in = site(c.input);
  // remote -> remote is another host's; an everywhere component's connection to a remote one is
  // made by that host with its own instance of it.
  if (out != Placement::Site::Local && in != Placement::Site::Local) return;
  const bool writer = out == Placement::Site::Local;
  core::PortBase& local = writer ? *c.output : *c.input;
  const core::ConnPolicy policy = placement_->crossHostPolicy(c.policy, c.spec->output);
  std::vector<std::string>& topics = writer ? writer_topics_ : reader_topics_;
  // One writer end per output port, however many remote inputs read it.
  if (writer && std::find(topics.begin(), topics.end(), policy.topic) != topics.end()) return;
  try {
    core::connectToTransport(local, policy);
  } catch (const std::exception& e) {
    journal.fail(where.text() + ": " + c.spec->output + " -> " + c.spec->input + " crosses hosts (" +
                 placement_->hostOf(c.output->owner()->name(), where) + " -> " +
                 placement_->hostOf(c.input->owner()->name(), where) + "): " + e.what());
  }
  topics.push_back(policy.topic);
  journal.record("the " + policy.transport + " end of " + local.fullName(), [this, &local, policy, writer] {
    for (const auto& channel : local.connections())
      if (channel->policy().transport == policy.transport && channel->policy().topic == policy.topic)
        core::disconnectPorts(channel->writer(), channel->reader());
    auto& made = writer ? writer_topics_ : reader_topics_;
    if (const auto it = std::find(made.rbegin(), made.rend(), policy.topic); it != made.rend())
      made.erase(std::next(it).base());
  });
}

}  // namespace cobra::deploy
