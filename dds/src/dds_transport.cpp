#include "cobra/dds/dds_transport.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <thread>

#include "cobra/core/data_type.hpp"
#include "cobra/core/error.hpp"
#include "cobra/dds/detail/participant.hpp"
#include "cobra/dds/register_type.hpp"

namespace cobra::dds {
namespace fdds = eprosima::fastdds::dds;
using detail::EndpointInfo;
using detail::EndpointQos;
using detail::Participant;

namespace {

constexpr const char* kQosKeys =
    "reliability (\"reliable\" or \"best_effort\"), depth (an integer >= 1), lease (s, a number > 0), "
    "durability (\"volatile\" or \"transient_local\")";

EndpointQos parseQos(const core::ConnPolicy& policy) {
  EndpointQos qos;
  qos.depth = policy.kind == core::ConnPolicy::Kind::Data ? 1 : static_cast<int>(policy.size);
  for (const auto& [key, value] : policy.options) {
    const std::string bad = "dds qos." + key + " = \"" + value + "\": expected ";
    if (key == "reliability") {
      if (value != "reliable" && value != "best_effort") throw core::Error(bad + "\"reliable\" or \"best_effort\"");
      qos.reliable = value == "reliable";
    } else if (key == "durability") {
      if (value != "volatile" && value != "transient_local") throw core::Error(bad + "\"volatile\" or \"transient_local\"");
      qos.transient_local = value == "transient_local";
    } else if (key == "depth") {
      // The port text parsers (data_type.hpp): the whole value must be the number.
      int depth = 0;
      if (!core::DataTypeTraits<int>::parse(value, depth) || depth < 1 || depth > 1000000)
        throw core::Error(bad + "an integer >= 1 (samples)");
      qos.depth = depth;
    } else if (key == "lease") {
      double lease = 0.0;
      if (!core::DataTypeTraits<double>::parse(value, lease) || !(lease > 0.0) || !std::isfinite(lease))
        throw core::Error(bad + "a number of seconds > 0, e.g. 0.1");
      qos.lease = lease;
    } else {
      throw core::Error("unknown dds qos key '" + key + "'; allowed keys: " + kQosKeys);
    }
  }
  return qos;
}

/// The binding of the port's type. @throws core::Error naming the type and how to register it.
const detail::Binding& bindingOf(const core::PortBase& port) {
  if (const detail::Binding* binding = detail::findBinding(port.type().id)) return *binding;
  throw core::Error("the dds transport carries no " + std::string(port.type().name) +
                    ": register it once, where the type is defined, with cobra::dds::registerDdsType<T>() "
                    "(cobra/dds/register_type.hpp; a record has a DDS wire of its own, another type needs a "
                    "cobra::dds::DdsCodec<T>); registered: " + detail::registeredDdsTypes());
}

EndpointInfo endpointInfo(const detail::Binding& binding, const core::PortBase& port, const core::ConnPolicy& policy,
                          bool writer) {
  return EndpointInfo{DdsTransport::ddsTopic(policy.topic), binding.dds_type, std::string(port.type().name),
                      port.fullName(), writer, parseQos(policy)};
}

}  // namespace

DdsTransport::DdsTransport(Options options) : participant_(std::make_shared<Participant>(options)) {
  registerBuiltinWires();  // cobra's own types (core::BuiltinDataTypes), once per process
}

DdsTransport::~DdsTransport() = default;

std::string DdsTransport::ddsTopic(const std::string& topic) {
  const std::string name = !topic.empty() && topic.front() == '/' ? topic.substr(1) : topic;
  const bool valid = !name.empty() && std::isdigit(static_cast<unsigned char>(name.front())) == 0 &&
                     name.back() != '/' && name.find("//") == std::string::npos &&
                     std::all_of(name.begin(), name.end(), [](unsigned char c) {
                       return std::isalnum(c) != 0 || c == '_' || c == '/';
                     });
  if (!valid)
    throw core::Error("dds topic '" + topic +
                      "' is not a ROS 2 topic name: expected letters, digits and '_' in '/'-separated parts, "
                      "not starting with a digit, e.g. \"needle/pose\"");
  return "rt/" + name;
}

void DdsTransport::check(const core::ConnPolicy& policy) const {
  ddsTopic(policy.topic);
  parseQos(policy);
}

void DdsTransport::makeWriterEnd(core::OutputPortBase& output, const core::ConnPolicy& policy, core::PortBase* peer) {
  check(policy);
  const detail::Binding& binding = bindingOf(output);
  binding.make_writer(participant_, output, policy, peer, endpointInfo(binding, output, policy, true));
}

void DdsTransport::makeReaderEnd(core::InputPortBase& input, const core::ConnPolicy& policy, core::PortBase* peer) {
  check(policy);
  const detail::Binding& binding = bindingOf(input);
  binding.make_reader(participant_, input, policy, peer, endpointInfo(binding, input, policy, false));
}

core::OutputPort<core::Event>& DdsTransport::events() { return participant_->events(); }

std::vector<std::string> DdsTransport::problems() const { return participant_->problems(); }

bool DdsTransport::waitForMatch(const std::string& topic, std::chrono::milliseconds timeout) const {
  const std::string name = ddsTopic(topic);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!participant_->allMatched(name)) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

std::vector<DdsTransport::RemoteParticipant> DdsTransport::participants() const { return participant_->participants(); }

std::optional<DdsTransport::RemoteParticipant> DdsTransport::waitForParticipant(const std::string& name,
                                                                                std::chrono::milliseconds timeout) const {
  return participant_->waitForParticipant(name, timeout);
}

std::string DdsTransport::guidPrefix() const { return participant_->guidPrefix(); }

std::shared_ptr<DdsTransport> registerDdsTransport(DdsTransport::Options options, const std::string& name) {
  const std::string doc = "Fast DDS, domain " + std::to_string(options.domain);
  auto transport = std::make_shared<DdsTransport>(std::move(options));
  core::TransportRegistry::add(name, doc, "cobra_dds", transport);
  return transport;
}

}  // namespace cobra::dds
