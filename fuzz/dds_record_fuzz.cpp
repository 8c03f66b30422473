// libFuzzer target: the DDS deserialiser of a record type (dds/record_wire.hpp) on arbitrary
// payloads, as a peer could send them under the record's type name: the dds tests' ProbeReading
// (a bool, doubles, an int, a string, a sequence, a nested record, KDL.Frame, Event and Twist
// carried by their ROS 2 messages). The first input byte chooses whether a valid little-endian
// CDR encapsulation is put before the rest (so most inputs reach the fields). Deserialising must
// return false or a value, never throw or crash; a value read must serialise, within the size
// its type support gives, and read back the same (the rotation to rounding: it travels as a
// quaternion).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "cobra/dds/codec.hpp"
#include "test_records.hpp"

namespace {

using cobra::dds::test::ProbeReading;
using eprosima::fastrtps::rtps::SerializedPayload_t;

bool bitwise(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool bitwise(const KDL::Vector& a, const KDL::Vector& b) {
  return bitwise(a.x(), b.x()) && bitwise(a.y(), b.y()) && bitwise(a.z(), b.z());
}

/// The first field that differs between two reads, or nullptr.
const char* differingField(const ProbeReading& a, const ProbeReading& b) {
  bool profile = a.profile.size() == b.profile.size();
  for (std::size_t i = 0; profile && i < a.profile.size(); ++i) profile = bitwise(a.profile[i], b.profile[i]);
  if (a.valid != b.valid) return "valid";
  if (!bitwise(a.depth, b.depth)) return "depth";
  if (a.label != b.label) return "label";
  if (!bitwise(a.pose.p, b.pose.p)) return "pose.p";
  if (!KDL::Equal(a.pose.M, b.pose.M, 1e-9)) return "pose.M";
  if (a.count != b.count) return "count";
  if (!bitwise(a.gains.stiffness, b.gains.stiffness) || a.gains.samples != b.gains.samples ||
      a.gains.enabled != b.gains.enabled)
    return "gains";
  if (!profile) return "profile";
  if (a.last.name != b.last.name || a.last.source != b.last.source || a.last.stamp != b.last.stamp) return "last";
  if (!bitwise(a.motion.vel, b.motion.vel) || !bitwise(a.motion.rot, b.motion.rot)) return "motion";
  return nullptr;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static cobra::dds::RecordPubSubType<ProbeReading> type;
  if (size < 1) return 0;
  const bool encapsulate = (data[0] & 1) != 0;
  std::vector<std::uint8_t> bytes;
  if (encapsulate) bytes = {0x00, 0x01, 0x00, 0x00};  // CDR_LE, no options
  bytes.insert(bytes.end(), data + 1, data + size);

  SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
  if (!bytes.empty()) std::memcpy(payload.data, bytes.data(), bytes.size());
  payload.length = static_cast<std::uint32_t>(bytes.size());
  ProbeReading read;
  if (!type.deserialize(&payload, &read)) return 0;

  // What was read is a record: it serialises within its size and reads back the same.
  const std::uint32_t needed = type.getSerializedSizeProvider(&read)();
  SerializedPayload_t again(needed);
  if (!type.serialize(&read, &again) || again.length != needed) std::abort();
  ProbeReading back;
  if (!type.deserialize(&again, &back)) {
    std::fprintf(stderr, "fuzz: a record read does not read back after serialising\n");
    std::abort();
  }
  if (const char* field = differingField(read, back)) {
    std::fprintf(stderr, "fuzz: field %s of a record read differs after serialising and reading back\n", field);
    std::abort();
  }
  return 0;
}
