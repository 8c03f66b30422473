#pragma once
// A DDS type support's bytes in the dds tests: what a TopicDataType writes for a value, and
// whether it reads given bytes back, through Fast DDS's serialized payload as a DataWriter and a
// DataReader would (no participant).
#include <cstdint>
#include <cstring>
#include <vector>

#include <fastdds/rtps/common/SerializedPayload.h>

#include <gtest/gtest.h>

namespace cobra::dds::test {

/// The bytes of `value` serialised by `type`, in a payload of the size the type asks for it.
template <class Type, class Value>
std::vector<unsigned char> serialised(Type& type, Value& value) {
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&value)());
  EXPECT_TRUE(type.serialize(&value, &payload));
  return {payload.data, payload.data + payload.length};
}

/// Whether `type` reads `bytes` (a payload of exactly that length) into `value`.
template <class Type, class Value>
bool deserialised(Type& type, const std::vector<unsigned char>& bytes, Value& value) {
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
  std::memcpy(payload.data, bytes.data(), bytes.size());
  payload.length = static_cast<std::uint32_t>(bytes.size());
  return type.deserialize(&payload, &value);
}

}  // namespace cobra::dds::test
