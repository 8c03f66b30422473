#include "console.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <thread>

#include "cobra/deploy/suggest.hpp"

namespace cobra::tools {
namespace {

using Words = std::vector<std::string>;

std::atomic<bool> g_interrupted{false};

/// How long `trace` waits for samples: simulated time on the lockstep clock, wall time otherwise.
constexpr std::chrono::seconds kTraceLimit{10};
/// Lockstep clock increment while tracing (s); a sample is stamped with the end of its slice.
constexpr std::chrono::milliseconds kTraceSlice{1};
/// Queue of the temporary probe a trace uses: a 1 kHz writer and a 1 ms slice fill ~1 a slice.
constexpr std::size_t kTraceQueue = 1024;
/// Queue of the console's event writers, so that events sent quickly are all delivered.
constexpr std::size_t kEventQueue = 64;

std::string joined(const std::vector<std::string>& names, std::string_view separator = ", ") {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : std::string(separator)) + name;
  return text;
}

bool startsWith(std::string_view text, std::string_view prefix) { return text.substr(0, prefix.size()) == prefix; }

}  // namespace

/// One console command: its name, how to call it, what it does, and its handler.
struct Console::Command {
  std::string_view name;
  std::string_view usage;
  std::string_view summary;
  void (Console::*handler)(const Words&);
  /// What the arguments complete to: "component", "port", "property", "operation", "command",
  /// "apply" or "" (nothing).
  std::string_view completes;
};

const std::vector<Console::Command>& Console::commands() {
  static const std::vector<Command> table = {
      {"help", "help [COMMAND]", "list the commands, or explain one", &Console::help, "command"},
      {"ls", "ls [COMPONENT]", "list the components, or one component's ports, properties and operations",
       &Console::list, "component"},
      {"cd", "cd COMPONENT | cd ..", "go into a component (its members can then be named alone)",
       &Console::changeComponent, "component"},
      {"read", "read PORT", "the latest sample of a port (of what feeds it, for an input)", &Console::readPort, "port"},
      {"write", "write PORT VALUE", "write one sample into an input port", &Console::writePort, "port"},
      {"get", "get PROPERTY", "a property's value", &Console::getProperty, "property"},
      {"set", "set PROPERTY VALUE", "set a property (a running component takes it between two updates)",
       &Console::setProperty, "property"},
      {"call", "call OPERATION [ARG...]", "call an operation; also OPERATION(ARG, ...)", nullptr, "operation"},
      {"event", "event NAME [PORT]", "send an event (default: the current component's Event input)",
       &Console::sendEvent, "port"},
      {"trace", "trace PORT [COUNT]", "print the next COUNT (default 10) samples of a port with their time",
       &Console::trace, "port"},
      {"configure", "configure [COMPONENT]", "PreOperational -> Stopped", &Console::lifecycle, "component"},
      {"start", "start [COMPONENT]", "Stopped -> Running", &Console::lifecycle, "component"},
      {"stop", "stop [COMPONENT]", "Running -> Stopped", &Console::lifecycle, "component"},
      {"cleanup", "cleanup [COMPONENT]", "Stopped -> PreOperational", &Console::lifecycle, "component"},
      {"recover", "recover [COMPONENT]", "Exception -> PreOperational", &Console::lifecycle, "component"},
      {"step", "step SECONDS", "advance the lockstep clock (console started with --sim)", &Console::step, ""},
      {"time", "time", "the deployment's clock, in s", nullptr, ""},
      {"deployments", "deployments", "the named deployments and configurations, and the current ones", nullptr, ""},
      {"apply", "apply deployment|configuration NAME", "switch to a named deployment or configuration",
       &Console::apply, "apply"},
      {"load", "load FILE", "run a Lua deployment file in this console's deployment", &Console::load, ""},
      {"lua", "lua CODE", "run a line of Lua (the deployer's functions and component references)", nullptr, ""},
      {"quit", "quit", "leave the console (also: exit, Ctrl-D)", nullptr, ""},
  };
  return table;
}

Console::Console(deploy::Configurator& configurator, deploy::LuaDeployer& deployer, std::ostream& out)
    : configurator_(configurator), deployer_(deployer), out_(out) {}

// The probes and feeders disconnect themselves from the deployment's ports when destroyed.
Console::~Console() = default;

void Console::interrupt() { g_interrupted.store(true); }

std::vector<std::string> splitCommandLine(std::string_view line) {
  Words words;
  std::string word;
  bool in_word = false, quoted = false;
  int brackets = 0;
  for (char c : line) {
    if (c == '#' && !quoted && brackets == 0) break;
    if (c == '"' && brackets == 0) {
      quoted = !quoted;
      in_word = true;
      continue;
    }
    if (!quoted && brackets == 0 && (c == ' ' || c == '\t')) {
      if (in_word) words.push_back(std::move(word));
      word.clear();
      in_word = false;
      continue;
    }
    if (!quoted) brackets += c == '[' ? 1 : c == ']' ? -1 : 0;
    word += c;
    in_word = true;
  }
  if (in_word) words.push_back(std::move(word));
  return words;
}

std::string Console::prompt() const { return current_.empty() ? "cobra> " : "cobra:" + current_ + "> "; }

bool Console::execute(std::string_view line) {
  g_interrupted.store(false);
  const Words words = splitCommandLine(line);
  if (words.empty()) return true;
  if (words[0] == "quit" || words[0] == "exit") return false;
  try {
    run(words, line);
  } catch (const std::exception& e) {
    out_ << "error: " << e.what() << "\n";
  }
  out_.flush();
  return true;
}

void Console::run(const Words& words, std::string_view line) {
  const std::string& name = words[0];
  if (name == "time") return showTime();
  if (name == "deployments") return listDeployments();
  if (name == "lua") return runLua(line);
  if (name == "call") {
    if (words.size() < 2) throw core::Error("usage: call OPERATION [ARG...]");
    return callOperation(words[1], Words(words.begin() + 2, words.end()));
  }
  for (const Command& command : commands())
    if (command.name == name && command.handler != nullptr) return (this->*command.handler)(words);
  runExpression(line);
}

// TaskBrowser-style expressions: `Comp.prop = 2`, `Comp.op(1, 2)`, `Comp.port`, `prop`.
void Console::runExpression(std::string_view line) {
  std::string text(line);
  text.erase(0, text.find_first_not_of(" \t"));
  text.erase(text.find_last_not_of(" \t") + 1);
  if (const auto open = text.find('('); open != std::string::npos && text.back() == ')') {
    Words arguments;
    std::string inside = text.substr(open + 1, text.size() - open - 2);
    int depth = 0;
    std::string argument;
    for (char c : inside) {  // commas inside brackets belong to a value such as [1, 2, 3]
      depth += c == '[' ? 1 : c == ']' ? -1 : 0;
      if (c == ',' && depth == 0) {
        arguments.push_back(argument);
        argument.clear();
      } else {
        argument += c;
      }
    }
    for (auto& a : arguments) a = splitCommandLine(a).empty() ? "" : joined(splitCommandLine(a), " ");
    if (!splitCommandLine(argument).empty()) arguments.push_back(joined(splitCommandLine(argument), " "));
    return callOperation(text.substr(0, open), arguments);
  }
  if (const auto equals = text.find('='); equals != std::string::npos) {
    std::string path = text.substr(0, equals), value = text.substr(equals + 1);
    path.erase(path.find_last_not_of(" \t") + 1);
    value.erase(0, value.find_first_not_of(" \t"));
    return setProperty({"set", path, value});
  }
  const Words words = splitCommandLine(text);
  if (words.size() == 1) {
    auto [owner, name] = member(words[0]);
    if (owner->findPort(name) != nullptr) return readPort({"read", words[0]});
    if (owner->findProperty(name) != nullptr) return getProperty({"get", words[0]});
    if (owner->findOperation(name) != nullptr) return callOperation(words[0], {});
    if (words[0].find('.') == std::string::npos && configurator_.getReferences().find(words[0]) != nullptr)
      return list({"ls", words[0]});
  }
  std::vector<std::string> names;
  for (const Command& command : commands()) names.emplace_back(command.name);
  throw core::Error("unknown command '" + words[0] + "'" + deploy::suggestionText(words[0], names, "commands") +
                    " (or name a port, property or operation; type help)");
}

void Console::help(const Words& words) {
  if (words.size() > 1) {
    for (const Command& command : commands())
      if (command.name == words[1]) {
        out_ << command.usage << "\n  " << command.summary << "\n";
        return;
      }
    throw core::Error("no command named '" + words[1] + "'; type help for the list");
  }
  for (const Command& command : commands())
    out_ << "  " << std::left << std::setw(38) << command.usage << command.summary << "\n";
  out_ << "Members of the current component can be named alone; others as Component.member.\n"
          "Expressions: Comp.port (read), Comp.prop (get), Comp.prop = VALUE (set), Comp.op(ARG, ...) (call).\n";
}

void Console::list(const Words& words) {
  if (words.size() > 1 || !current_.empty()) {
    out_ << core::toText(core::describe(component(words.size() > 1 ? words[1] : "")));
    return;
  }
  const auto all = configurator_.getReferences().components();
  if (all.empty()) out_ << "no components (load a deployment file: load FILE)\n";
  for (const core::Component* c : all)
    out_ << "  " << std::left << std::setw(20) << c->name() << std::setw(12) << core::toString(c->role())
         << std::setw(15) << core::toString(c->state()) << c->activity().describe() << "\n";
}

void Console::changeComponent(const Words& words) {
  if (words.size() != 2) throw core::Error("usage: cd COMPONENT | cd ..");
  if (words[1] == ".." || words[1] == "/") {
    current_.clear();
    return;
  }
  current_ = component(words[1]).name();
}

core::Component& Console::component(std::string_view name) const {
  if (name.empty() || name == ".") {
    if (current_.empty()) throw core::Error("no current component: name one, or cd into one");
    return configurator_.getReferences().get(current_);
  }
  return configurator_.getReferences().get(name);
}

std::pair<core::Component*, std::string> Console::member(std::string_view path) const {
  const auto dot = path.rfind('.');
  if (dot == std::string_view::npos) return {&component(""), std::string(path)};
  return {&component(path.substr(0, dot)), std::string(path.substr(dot + 1))};
}

core::PortBase& Console::port(std::string_view path) const {
  auto [owner, name] = member(path);
  return owner->port(name);
}

core::PropertyBase& Console::property(std::string_view path) const {
  auto [owner, name] = member(path);
  return owner->property(name);
}

core::OutputPortBase& Console::sourceOf(core::PortBase& watched) const {
  if (watched.direction() == core::PortDirection::Output) return static_cast<core::OutputPortBase&>(watched);
  for (const auto& channel : watched.connections())
    if (channel->writer().owner() != nullptr) return static_cast<core::OutputPortBase&>(channel->writer());
  throw core::Error("input port " + watched.fullName() + " is not connected to any component's output: nothing to read");
}

core::InputPortBase& Console::probe(core::PortBase& watched) {
  core::OutputPortBase& source = sourceOf(watched);
  const std::string key = source.fullName();
  auto found = probes_.find(key);
  if (found == probes_.end()) {
    auto reader = source.makeReader("console_probe", "the console's view of " + key);
    source.connectTo(*reader, core::ConnPolicy::data());
    found = probes_.emplace(key, std::move(reader)).first;
  }
  return *found->second;
}

core::OutputPortBase& Console::feeder(core::PortBase& fed) {
  if (fed.direction() != core::PortDirection::Input)
    throw core::Error("port " + fed.fullName() + " is an output port, written by " + fed.owner()->name() +
                      "; the console writes only into input ports");
  const std::string key = fed.fullName();
  auto found = feeders_.find(key);
  if (found == feeders_.end()) {
    auto writer = static_cast<core::InputPortBase&>(fed).makeWriter("console_writer", "the console's writer into " + key);
    const bool logic = fed.type().kind == core::DataKind::Logic;
    writer->connectTo(fed, logic ? core::ConnPolicy::buffer(kEventQueue) : core::ConnPolicy::data());
    found = feeders_.emplace(key, std::move(writer)).first;
  }
  return *found->second;
}

void Console::readPort(const Words& words) {
  if (words.size() != 2) throw core::Error("usage: read PORT");
  core::PortBase& p = port(words[1]);
  std::string text;
  const core::FlowStatus status = probe(p).readText(text);
  if (status == core::FlowStatus::NoData) {
    out_ << p.fullName() << ": no sample yet since the console started watching it; "
         << (configurator_.mode() == deploy::ClockMode::Simulation ? "step the clock" : "wait") << " and read again\n";
    return;
  }
  out_ << p.fullName() << " = " << text;
  if (!p.unit().empty() && p.unit() != "1") out_ << " [" << p.unit() << "]";
  out_ << (status == core::FlowStatus::NewData ? "" : " (old)") << "\n";
}

void Console::writePort(const Words& words) {
  if (words.size() < 3) throw core::Error("usage: write PORT VALUE");
  core::PortBase& p = port(words[1]);
  const std::string value = joined(Words(words.begin() + 2, words.end()), " ");
  const core::WriteStatus status = feeder(p).writeText(value);
  out_ << "wrote " << value << " to " << p.fullName() << (status == core::WriteStatus::Dropped ? " (dropped: queue full)" : "")
       << "\n";
}

void Console::getProperty(const Words& words) {
  if (words.size() != 2) throw core::Error("usage: get PROPERTY");
  const core::PropertyBase& p = property(words[1]);
  out_ << words[1] << " = " << p.valueText();
  if (!p.unit().empty() && p.unit() != "1") out_ << " [" << p.unit() << "]";
  out_ << "\n";
}

void Console::setProperty(const Words& words) {
  if (words.size() < 3) throw core::Error("usage: set PROPERTY VALUE");
  auto [owner, name] = member(words[1]);
  core::PropertyBase& p = owner->property(name);
  p.setFromText(joined(Words(words.begin() + 2, words.end()), " "));
  out_ << owner->name() << "." << name << " = " << p.valueText() << "\n";
}

void Console::callOperation(const std::string& path, const Words& arguments) {
  auto [owner, name] = member(path);
  const std::string result = owner->operation(name).invokeFromText(arguments);
  out_ << owner->name() << "." << name << "(" << joined(arguments) << ")" << (result.empty() ? "" : " = " + result)
       << "\n";
}

void Console::sendEvent(const Words& words) {
  if (words.size() < 2 || words.size() > 3) throw core::Error("usage: event NAME [PORT]");
  core::PortBase* target = nullptr;
  if (words.size() == 3) {
    target = &port(words[2]);
  } else {
    for (core::PortBase* p : component("").ports())
      if (p->direction() == core::PortDirection::Input && p->type().name == core::typeInfo<core::Event>().name) {
        target = p;
        break;
      }
    if (target == nullptr)
      throw core::Error("component '" + current_ + "' has no input port of type Event; name one: event " + words[1] +
                        " Component.inputEvents");
  }
  if (target->type().name != core::typeInfo<core::Event>().name)
    throw core::Error("port " + target->fullName() + " carries " + std::string(target->type().name) +
                      ", not events; use write for data");
  std::ostringstream event;
  event << words[1] << " from console at " << now() << " s";
  const core::WriteStatus status = feeder(*target).writeText(event.str());
  out_ << "sent " << words[1] << " to " << target->fullName()
       << (status == core::WriteStatus::Dropped ? " (dropped: the port's queue is full)" : "") << "\n";
}

void Console::trace(const Words& words) {
  if (words.size() < 2 || words.size() > 3) throw core::Error("usage: trace PORT [COUNT]");
  long count = 10;
  if (words.size() == 3) {
    std::size_t used = 0;
    try {
      count = std::stol(words[2], &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != words[2].size() || count < 1) throw core::Error("trace: COUNT must be a whole number >= 1, got '" + words[2] + "'");
  }
  core::OutputPortBase& source = sourceOf(port(words[1]));
  auto reader = source.makeReader("console_trace", "the console's trace of " + source.fullName());
  source.connectTo(*reader, core::ConnPolicy::buffer(kTraceQueue));

  const bool simulated = configurator_.mode() == deploy::ClockMode::Simulation;
  const auto start = std::chrono::steady_clock::now();
  const auto sim_start = simulated ? configurator_.clock().now() : std::chrono::nanoseconds(0);
  long seen = 0;
  std::string text;
  // On the lockstep clock a sample is stamped with the start of the slice it was written in:
  // the exact instant for activities on whole milliseconds. In real time, when it was read.
  double stamp = now();
  while (seen < count && !g_interrupted.load()) {
    while (seen < count && reader->readText(text) == core::FlowStatus::NewData) {
      out_ << "  t = " << std::fixed << std::setprecision(4) << (simulated ? stamp : now()) << std::defaultfloat
           << " s  " << source.fullName() << " = " << text << "\n";
      ++seen;
    }
    if (seen == count) break;
    if (simulated) {
      if (configurator_.clock().now() - sim_start >= kTraceLimit) break;
      stamp = now();
      configurator_.clock().advance(kTraceSlice);
    } else {
      if (std::chrono::steady_clock::now() - start >= kTraceLimit) break;
      std::this_thread::sleep_for(kTraceSlice);
    }
  }
  out_.flush();
  if (seen < count)
    out_ << "trace stopped after " << seen << " of " << count << " samples ("
         << (g_interrupted.load() ? "interrupted" : "no more within " + std::to_string(kTraceLimit.count()) + " s") << ")\n";
}

void Console::lifecycle(const Words& words) {
  if (words.size() > 2) throw core::Error("usage: " + words[0] + " [COMPONENT]");
  core::Component& c = component(words.size() == 2 ? words[1] : "");
  core::Result result;
  if (words[0] == "configure") result = c.configure();
  else if (words[0] == "start") result = c.start();
  else if (words[0] == "stop") result = c.stop();
  else if (words[0] == "cleanup") result = c.cleanup();
  else result = c.recover();
  if (!result) throw core::Error("cannot " + words[0] + " " + c.name() + ": " + result.message);
  out_ << c.name() << ": " << core::toString(c.state()) << "\n";
}

void Console::step(const Words& words) {
  if (configurator_.mode() != deploy::ClockMode::Simulation)
    throw core::Error("step needs the lockstep clock: start the console with --sim");
  double seconds = 0.0;
  std::size_t used = 0;
  try {
    if (words.size() == 2) seconds = std::stod(words[1], &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (words.size() != 2 || used != words[1].size() || !(seconds > 0.0) || seconds > 1e6)
    throw core::Error("usage: step SECONDS, with 0 < SECONDS <= 1e6 (e.g. step 0.01)");
  configurator_.clock().advance(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(seconds)));
  showTime();
}

double Console::now() const {
  if (configurator_.mode() == deploy::ClockMode::Simulation)
    return std::chrono::duration<double>(configurator_.clock().now()).count();
  static const auto start = std::chrono::steady_clock::now();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Console::showTime() {
  out_ << "t = " << now() << " s ("
       << (configurator_.mode() == deploy::ClockMode::Simulation ? "lockstep simulation clock" : "real time") << ")\n";
}

void Console::listDeployments() {
  const deploy::DeploymentSet& set = configurator_.deploymentSet();
  out_ << "deployments: " << (set.deploymentNames().empty() ? "(none)" : joined(set.deploymentNames()))
       << "; current: " << (configurator_.currentDeployment().empty() ? "(none)" : configurator_.currentDeployment())
       << "\nconfigurations: " << (set.configurationNames().empty() ? "(none)" : joined(set.configurationNames()))
       << "; current: "
       << (configurator_.currentConfiguration().empty() ? "(none)" : configurator_.currentConfiguration()) << "\n";
}

void Console::apply(const Words& words) {
  if (words.size() != 3 || (words[1] != "deployment" && words[1] != "configuration"))
    throw core::Error("usage: apply deployment NAME | apply configuration NAME");
  if (words[1] == "deployment") {
    for (const deploy::LintViolation& v : configurator_.applyDeployment(words[2])) out_ << "warning: " << v.message << "\n";
  } else {
    configurator_.applyConfiguration(words[2]);
  }
  out_ << "applied " << words[1] << " " << words[2] << "\n";
}

void Console::runLua(std::string_view line) {
  const auto start = line.find("lua");
  std::string code(line.substr(start + 3));
  if (code.find_first_not_of(" \t") == std::string::npos) throw core::Error("usage: lua CODE (e.g. lua print(1 + 1))");
  std::fflush(stdout);  // Lua's print writes to stdout directly
  deployer_.run(code, "console");
  std::fflush(stdout);
}

void Console::load(const Words& words) {
  if (words.size() != 2) throw core::Error("usage: load FILE");
  const std::size_t before = configurator_.getReferences().components().size();
  deployer_.runFile(words[1]);
  for (const std::string& warning : configurator_.warnings()) out_ << "warning: " << warning << "\n";
  out_ << "loaded " << words[1] << ": " << configurator_.getReferences().components().size() - before
       << " new component(s)\n";
}

std::vector<std::string> Console::complete(std::string_view line) const {
  const Words words = splitCommandLine(line);
  const bool new_word = line.empty() || line.back() == ' ' || line.back() == '\t';
  const std::string typed = new_word || words.empty() ? "" : words.back();
  const std::size_t index = words.size() - (new_word || words.empty() ? 0 : 1);

  std::string_view kind = "first";
  if (index > 0) {
    kind = "";
    for (const Command& command : commands())
      if (command.name == words[0]) kind = command.completes;
    if (kind == "apply" && index == 2)
      kind = words[1] == "deployment" ? "deployment" : words[1] == "configuration" ? "configuration" : "";
    else if (kind == "apply" && index > 2)
      kind = "";
  }

  std::vector<std::string> candidates;
  const core::ComponentRegistry& registry = configurator_.getReferences();
  auto members = [&](const core::Component& c, const std::string& prefix) {
    if (kind == "first" || kind == "port")
      for (const core::PortBase* p : c.ports()) candidates.push_back(prefix + p->name());
    if (kind == "first" || kind == "property")
      for (const core::PropertyBase* p : c.properties()) candidates.push_back(prefix + p->name());
    if (kind == "first" || kind == "operation")
      for (const core::OperationBase* o : c.operations()) candidates.push_back(prefix + o->name());
  };
  if (kind == "first" || kind == "command")
    for (const Command& command : commands()) candidates.emplace_back(command.name);
  if (kind == "component") {
    for (const core::Component* c : registry.components()) candidates.push_back(c->name());
    if (words[0] == "cd") candidates.emplace_back("..");
  }
  if (kind == "apply") candidates = {"deployment", "configuration"};
  if (kind == "deployment") candidates = configurator_.deploymentSet().deploymentNames();
  if (kind == "configuration") candidates = configurator_.deploymentSet().configurationNames();
  if (kind == "first" || kind == "port" || kind == "property" || kind == "operation") {
    if (const auto dot = typed.rfind('.'); dot != std::string::npos) {
      if (const core::Component* c = registry.find(typed.substr(0, dot))) members(*c, typed.substr(0, dot + 1));
    } else {
      for (const core::Component* c : registry.components()) candidates.push_back(c->name() + ".");
      if (const core::Component* c = registry.find(current_)) members(*c, "");
    }
  }
  std::vector<std::string> matches;
  for (std::string& candidate : candidates)
    if (startsWith(candidate, typed)) matches.push_back(std::move(candidate));
  std::sort(matches.begin(), matches.end());
  matches.erase(std::unique(matches.begin(), matches.end()), matches.end());
  return matches;
}

}  // namespace cobra::tools
