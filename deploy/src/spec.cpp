#include "cobra/deploy/spec.hpp"

#include <algorithm>
#include <cctype>

#include "cobra/core/error.hpp"
#include "cobra/core/transport.hpp"

namespace cobra::deploy {
namespace {

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

}  // namespace

std::string SourceLocation::text() const {
  if (file.empty() && line <= 0) return "<no location>";
  const std::string name = file.empty() ? "<unknown file>" : file;
  return line > 0 ? name + ":" + std::to_string(line) : name;
}

bool ActivitySpec::sameActivity(const ActivitySpec& other) const {
  return period == other.period && priority == other.priority && lowercase(scheduler) == lowercase(other.scheduler) &&
         own_pace == other.own_pace && max_age == other.max_age;
}

PortPath parsePortPath(const std::string& text, const SourceLocation& where) {
  const auto dot = text.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == text.size())
    throw core::Error(where.text() + ": '" + text + "' is not a port path; write it as \"Component.port\"");
  return {text.substr(0, dot), text.substr(dot + 1)};
}

namespace {

core::ConnPolicy localPolicy(const ConnPolicySpec& spec, const SourceLocation& where) {
  const std::string type = lowercase(spec.type);
  if (type == "data") return core::ConnPolicy::data();
  const bool buffer = type == "buffer";
  const bool circular = type == "circular" || type == "circular_buffer";
  if (!buffer && !circular)
    throw core::Error(where.text() + ": unknown connection policy type '" + spec.type +
                      "'; use \"data\", \"buffer\" or \"circular\"");
  if (spec.size < 1)
    throw core::Error(where.text() + ": a " + type + " connection needs size >= 1, got " + std::to_string(spec.size));
  const auto size = static_cast<std::size_t>(spec.size);
  return buffer ? core::ConnPolicy::buffer(size) : core::ConnPolicy::circular(size);
}

}  // namespace

core::ConnPolicy toConnPolicy(const ConnPolicySpec& spec, const SourceLocation& where) {
  core::ConnPolicy policy = localPolicy(spec, where);
  if (spec.transport.empty()) {
    if (!spec.topic.empty() || !spec.qos.empty())
      throw core::Error(where.text() + ": conn_policy." + (spec.topic.empty() ? "qos" : "topic") +
                        " needs a transport: add transport = \"dds\" (or another registered transport)");
    return policy;
  }
  policy.transport = spec.transport;
  policy.topic = spec.topic;
  policy.options = spec.qos;
  try {
    core::TransportRegistry::get(spec.transport)->check(policy);
  } catch (const core::Error& e) {
    throw core::Error(where.text() + ": conn_policy: " + e.what());
  }
  return policy;
}

core::Scheduler toScheduler(const std::string& name, const SourceLocation& where) {
  const std::string key = lowercase(name);
  if (key == "oro_sched_rt" || key == "sched_fifo" || key == "fifo") return core::Scheduler::Fifo;
  if (key == "oro_sched_other" || key == "sched_other" || key == "other") return core::Scheduler::Other;
  throw core::Error(where.text() + ": unknown scheduler '" + name +
                    "'; use \"ORO_SCHED_RT\" (or \"SCHED_FIFO\") or \"ORO_SCHED_OTHER\" (or \"SCHED_OTHER\")");
}

}  // namespace cobra::deploy
