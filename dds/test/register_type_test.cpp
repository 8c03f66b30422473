// The types the dds transport carries (register_type.hpp): a record registered once crosses
// between two participants equal, field by field; a port of a type nobody registered is refused
// naming the type and how to register it; samples under the record's type name that are not a
// record (short, corrupted) are dropped by the reader, and the next good one arrives. Each test
// uses its own DDS domain (ctest runs tests in parallel).
#include "cobra/dds/register_type.hpp"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "cobra/core/port.hpp"
#include "cobra/test_support/test_support.hpp"
#include "dds_test_support.hpp"
#include "test_records.hpp"

namespace {
struct Unsent {
  double depth = 0.0;
};
// Registered only through core::TypeFacets, as a package's type reaches the transport of the
// `cobra` tool (whose dds registry is its package's own).
struct FacetOnly {
  double force = 0.0;
  int count = 0;
};
}  // namespace

template <>
struct cobra::core::DataTypeTraits<FacetOnly> : cobra::core::RecordTraits<FacetOnly> {
  static constexpr std::string_view name = "probe_msgs.FacetOnly";
  static constexpr auto fields = std::tuple{field("force", &FacetOnly::force, "N"), field("count", &FacetOnly::count)};
};

template <>
struct cobra::core::DataTypeTraits<Unsent> : cobra::core::RecordTraits<Unsent> {
  static constexpr std::string_view name = "probe_msgs.Unsent";
  static constexpr auto fields = std::tuple{field("depth", &Unsent::depth, "m")};
};

namespace cobra::dds {
namespace {

namespace fdds = eprosima::fastdds::dds;
using namespace std::chrono_literals;
using test::ProbeReading;
using test::RegisteredTransport;

TEST(DdsRegisterType, ARecordCrossesBetweenTwoParticipantsEqualFieldByField) {
  registerDdsType<ProbeReading>();
  RegisteredTransport a("dds_record_a", 205, "cobra_a");
  RegisteredTransport b("dds_record_b", 205, "cobra_b");
  core::OutputPort<ProbeReading> out("reading", "probe reading", "");
  core::InputPort<ProbeReading> in("reading", "probe reading", "");
  core::ConnPolicy policy = core::ConnPolicy::buffer(32);
  policy.options = {{"reliability", "reliable"}, {"depth", "32"}};
  core::connectToTransport(out, a.policy("probe/reading", policy));
  core::connectToTransport(in, b.policy("probe/reading", policy));
  ASSERT_TRUE(a.transport->waitForMatch("probe/reading", 5s));
  ASSERT_TRUE(b.transport->waitForMatch("probe/reading", 5s));

  for (int seed = 1; seed <= 20; ++seed) ASSERT_EQ(out.write(test::probeReading(seed)), core::WriteStatus::Written);
  std::vector<ProbeReading> got;
  ASSERT_TRUE(test::pollUntil([&] {
    ProbeReading r;
    while (in.read(r) == core::FlowStatus::NewData) got.push_back(r);
    return got.size() >= 20;
  }));
  ASSERT_EQ(got.size(), 20U);
  for (int seed = 1; seed <= 20; ++seed)
    EXPECT_TRUE(test::same(got[static_cast<std::size_t>(seed - 1)], test::probeReading(seed))) << "reading " << seed;
  EXPECT_TRUE(a.transport->problems().empty());
}

TEST(DdsRegisterType, APortOfAnUnregisteredTypeIsRefusedNamingItAndHowToRegisterIt) {
  RegisteredTransport dds("dds_unregistered", 206, "cobra");
  core::OutputPort<Unsent> out("out", "", "");
  const std::string message = test_support::messageOf([&] { core::connectToTransport(out, dds.policy("probe/unsent")); });
  EXPECT_EQ(message.substr(0, message.find("; registered: ")),
            "cannot connect out (probe_msgs.Unsent) to dds_unregistered topic 'probe/unsent': the dds transport carries "
            "no probe_msgs.Unsent: register it once, where the type is defined, with "
            "cobra::dds::registerDdsType<T>() (cobra/dds/register_type.hpp; a record has a DDS wire of its own, "
            "another type needs a cobra::dds::DdsCodec<T>)");
  // The registered types follow: cobra's built-in ones, registered by every transport.
  EXPECT_NE(message.find("double, int, bool, string, vector<double>, KDL.Vector, KDL.Rotation, KDL.Frame"),
            std::string::npos)
      << message;

  registerDdsType<Unsent>();  // once registered, the same port connects
  core::connectToTransport(out, dds.policy("probe/unsent"));
  EXPECT_TRUE(out.connected());
}

TEST(DdsRegisterType, ABindingPublishedOnlyAsATypeFacetIsFoundByTheTransport) {
  // What registerDdsType<T>() in another module (a package) leaves in this process: its
  // binding in core::TypeFacets, nothing in this module's registry.
  static const detail::Binding binding = detail::binding<FacetOnly>("probe_msgs.FacetOnly");
  ASSERT_TRUE(core::TypeFacets::set(typeid(FacetOnly), detail::facet, &binding));
  const auto own = ddsTypes();
  EXPECT_EQ(std::count(own.begin(), own.end(), "probe_msgs.FacetOnly"), 0);
  EXPECT_EQ(detail::findBinding(typeid(FacetOnly)), &binding);

  RegisteredTransport a("dds_facet_a", 211, "cobra_a");
  RegisteredTransport b("dds_facet_b", 211, "cobra_b");
  core::OutputPort<FacetOnly> out("sample", "", "");
  core::InputPort<FacetOnly> in("sample", "", "");
  core::ConnPolicy policy = core::ConnPolicy::buffer(8);
  policy.options = {{"reliability", "reliable"}, {"depth", "8"}};
  core::connectToTransport(out, a.policy("probe/facet", policy));
  core::connectToTransport(in, b.policy("probe/facet", policy));
  ASSERT_TRUE(a.transport->waitForMatch("probe/facet", 5s));
  ASSERT_TRUE(b.transport->waitForMatch("probe/facet", 5s));
  ASSERT_EQ(out.write(FacetOnly{12.5, 7}), core::WriteStatus::Written);
  FacetOnly got;
  ASSERT_TRUE(test::pollUntil([&] { return in.read(got) == core::FlowStatus::NewData; }));
  EXPECT_EQ(got.force, 12.5);
  EXPECT_EQ(got.count, 7);
}

TEST(DdsRegisterType, RegisterDdsTypePublishesItsBindingAsATypeFacet) {
  registerDdsType<ProbeReading>();
  const auto* published = static_cast<const detail::Binding*>(core::TypeFacets::get(typeid(ProbeReading), detail::facet));
  ASSERT_NE(published, nullptr);
  EXPECT_EQ(published->cobra_type, "probe_msgs.ProbeReading");
  EXPECT_NE(published->make_writer, nullptr);
}

TEST(DdsRegisterType, RegisteringAgainKeepsOneEntry) {
  registerBuiltinWires();
  registerDdsType<ProbeReading>();
  registerDdsType<ProbeReading>();
  registerBuiltinWires();
  const auto types = ddsTypes();
  EXPECT_EQ(std::count(types.begin(), types.end(), "probe_msgs.ProbeReading"), 1);
  EXPECT_EQ(std::count(types.begin(), types.end(), "KDL.Frame"), 1);
}

TEST(DdsRegisterType, TheIdlOfARegisteredRecordIsFoundByItsName) {
  registerBuiltinWires();
  registerDdsType<ProbeReading>();
  EXPECT_EQ(registeredIdl("probe_msgs.ProbeReading"), idlOf<ProbeReading>());
  EXPECT_EQ(test_support::messageOf([] { registeredIdl("KDL.Frame"); }),
            "'KDL.Frame' travels as the message geometry_msgs::msg::dds_::Pose_, not as a record: its IDL is that "
            "message's (cobra's are in dds/idl)");
  const std::string unknown = test_support::messageOf([] { registeredIdl("probe_msgs.Nothing"); });
  EXPECT_EQ(unknown.substr(0, unknown.find(';')), "no type 'probe_msgs.Nothing' is registered for DDS") << unknown;
}

/// A type support that claims the record's DDS type name and sends the bytes it is given (a
/// std::vector<unsigned char>) as they are: what a broken or hostile peer could publish.
class RawBytesType final : public fdds::TopicDataType {
 public:
  explicit RawBytesType(const std::string& name) {
    setName(name.c_str());
    m_typeSize = 4096;
  }
  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override {
    const auto& bytes = *static_cast<const std::vector<unsigned char>*>(data);
    if (bytes.size() > payload->max_size) return false;
    if (!bytes.empty()) std::memcpy(payload->data, bytes.data(), bytes.size());  // an empty sample has no data pointer
    payload->length = static_cast<std::uint32_t>(bytes.size());
    payload->encapsulation = CDR_LE;
    return true;
  }
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t*, void*) override { return false; }
  std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override {
    return [data] { return static_cast<std::uint32_t>(static_cast<const std::vector<unsigned char>*>(data)->size()); };
  }
  void* createData() override { return new std::vector<unsigned char>(); }
  void deleteData(void* data) override { delete static_cast<std::vector<unsigned char>*>(data); }
  bool getKey(void*, eprosima::fastrtps::rtps::InstanceHandle_t*, bool) override { return false; }
};

TEST(DdsRegisterType, SamplesThatAreNotTheRecordAreDroppedAndTheNextGoodOneArrives) {
  registerDdsType<ProbeReading>();
  const std::string type_name = wireTypeName<ProbeReading>();
  ASSERT_EQ(type_name, "probe_msgs::msg::dds_::ProbeReading_");
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  fdds::DomainParticipant* plain = factory->create_participant(207, fdds::PARTICIPANT_QOS_DEFAULT);
  fdds::TypeSupport raw(new RawBytesType(type_name));
  raw.register_type(plain);
  fdds::Topic* topic = plain->create_topic("rt/probe/junk", type_name, fdds::TOPIC_QOS_DEFAULT);
  fdds::DataWriterQos qos = fdds::DATAWRITER_QOS_DEFAULT;
  qos.history().kind = fdds::KEEP_ALL_HISTORY_QOS;
  fdds::DataWriter* writer = plain->create_publisher(fdds::PUBLISHER_QOS_DEFAULT)->create_datawriter(topic, qos);
  ASSERT_NE(writer, nullptr);

  RegisteredTransport dds("dds_junk", 207, "cobra");
  core::InputPort<ProbeReading> in("reading", "", "");
  core::ConnPolicy policy = core::ConnPolicy::buffer(32);
  policy.options = {{"reliability", "reliable"}, {"depth", "32"}};
  core::connectToTransport(in, dds.policy("probe/junk", policy));
  ASSERT_TRUE(dds.transport->waitForMatch("probe/junk", 5s));
  ASSERT_TRUE(test::pollUntil([&] {
    fdds::PublicationMatchedStatus matched;
    return writer->get_publication_matched_status(matched) == ReturnCode_t::RETCODE_OK && matched.current_count > 0;
  }));

  ProbeReading good = test::probeReading(5);
  RecordPubSubType<ProbeReading> record_type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(record_type.getSerializedSizeProvider(&good)());
  ASSERT_TRUE(record_type.serialize(&good, &payload));
  const std::vector<unsigned char> bytes(payload.data, payload.data + payload.length);
  std::vector<std::vector<unsigned char>> junk = {
      {}, {0x00, 0x01}, {bytes.begin(), bytes.begin() + 30}, {bytes.begin(), bytes.end() - 1}};
  junk.push_back(bytes);
  junk.back()[4] = 7;  // `valid`, a boolean, neither 0 nor 1
  junk.push_back(bytes);
  std::fill(junk.back().begin() + 20, junk.back().begin() + 24, 0xff);  // the label's length
  for (auto& sample : junk) ASSERT_EQ(writer->write(&sample), true);
  auto last = bytes;
  ASSERT_TRUE(writer->write(&last));

  std::vector<ProbeReading> got;
  ASSERT_TRUE(test::pollUntil([&] {
    ProbeReading r;
    while (in.read(r) == core::FlowStatus::NewData) got.push_back(r);
    return !got.empty();
  }));
  std::this_thread::sleep_for(100ms);  // nothing else comes
  ProbeReading r;
  while (in.read(r) == core::FlowStatus::NewData) got.push_back(r);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_TRUE(test::same(got.front(), good));

  plain->delete_contained_entities();
  factory->delete_participant(plain);
}

}  // namespace
}  // namespace cobra::dds
