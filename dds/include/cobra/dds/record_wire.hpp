#pragma once
/// @file
/// A record type (core/record.hpp) on DDS: a Fast DDS TopicDataType that serialises the record
/// field by field in CDR (XCDR1, as fastddsgen's code and ROS 2's rmw_fastrtps), key-less, with
/// the ROS 2 type name of its cobra name: "us.ProbeReading" travels as
/// `us::msg::dds_::ProbeReading_`, so a ROS 2 node built with the record's IDL (idl.hpp,
/// `idlOf<T>()`) as `us/msg/ProbeReading.idl` reads and writes the same bytes.
///
/// | field type                  | CDR (IDL)                                                       |
/// | --------------------------- | --------------------------------------------------------------- |
/// | double                      | double                                                          |
/// | int                         | long (32 bits)                                                  |
/// | bool                        | boolean                                                         |
/// | std::string                 | string                                                          |
/// | std::vector<double>         | sequence<double>                                                |
/// | a record                    | its struct, recursively                                         |
/// | any other type with a codec | its message (`DdsCodec<M>::Msg`), e.g. KDL.Frame as geometry_msgs/Pose |
///
/// Sizes follow fastddsgen's generated code: a record is bounded when every field is (no string,
/// no sequence, only bounded messages); the maximum size counts a string as 255 characters and a
/// sequence as 100 elements, and only sizes Fast DDS's first payload buffers: each sample gets
/// the exact size of its own fields (`getSerializedSizeProvider`).
///
/// Allocations (the transport's threads, never a component's): serialising writes into Fast DDS's
/// payload and allocates only for a field whose message has a sequence or a string longer than a
/// std::string keeps in place (KDL.JntArray, Event, TaskState: converted to their message first);
/// reading a string or sequence allocates what the received one needs beyond the value's capacity.

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <fastdds/rtps/common/SerializedPayload.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "cobra/core/record.hpp"

namespace cobra::dds {

template <class T>
struct DdsCodec;

namespace detail {

namespace cdr = eprosima::fastcdr;

/// True when `name` is "package.Type" (or "a.b.Type"): at least two parts, each an identifier
/// (a letter, then letters, digits or '_'), as IDL modules and a ROS 2 package and message need.
constexpr bool validRecordName(std::string_view name) {
  if (name.find('.') == std::string_view::npos) return false;
  bool start = true;
  for (const char c : name) {
    const bool letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
    const bool digit = c >= '0' && c <= '9';
    if (c == '.') {
      if (start) return false;  // an empty part
      start = true;
    } else if (start) {
      if (!letter) return false;
      start = false;
    } else if (!letter && !digit && c != '_') {
      return false;
    }
  }
  return !start;
}

/// "us.ProbeReading" → "us::msg::" + prefix + "ProbeReading" + suffix: the modules of the cobra
/// name's package, then ROS 2's `msg`.
inline std::string rosName(std::string_view cobra_name, std::string_view prefix, std::string_view suffix) {
  const std::size_t dot = cobra_name.rfind('.');
  std::string name;
  std::size_t begin = 0;
  while (begin < dot) {
    const std::size_t end = cobra_name.find('.', begin);
    name.append(cobra_name.substr(begin, end - begin)).append("::");
    begin = end + 1;
  }
  name.append("msg::").append(prefix).append(cobra_name.substr(dot + 1)).append(suffix);
  return name;
}

template <class M>
inline constexpr bool kPrimitiveField = std::is_same_v<M, double> || std::is_same_v<M, int> || std::is_same_v<M, bool> ||
                                        std::is_same_v<M, std::string> || std::is_same_v<M, std::vector<double>>;

template <class M>
using FieldMsg = typename DdsCodec<M>::Msg;

/// Whether the message of a field's type has a bounded size (no string, no sequence), asked of
/// its generated type support once.
template <class M>
bool messageBounded() {
  static const bool bounded = [] {
    typename DdsCodec<M>::PubSub support;
    return support.is_bounded();
  }();
  return bounded;
}

template <class T>
void serializeRecord(cdr::Cdr& out, const T& value);
template <class T>
void deserializeRecord(cdr::Cdr& in, T& value);
template <class T>
std::size_t recordSize(const T& value, std::size_t alignment);
template <class T>
std::size_t recordMaxSize(std::size_t alignment);
template <class T>
bool recordBounded();

template <class M>
void serializeField(cdr::Cdr& out, const M& value) {
  if constexpr (std::is_same_v<M, int>) {
    static_assert(sizeof(int) == 4, "cobra: int travels as a 32-bit long");
    out << static_cast<std::int32_t>(value);
  } else if constexpr (kPrimitiveField<M>) {
    out << value;
  } else if constexpr (core::RecordDataType<M>) {
    serializeRecord(out, value);
  } else {
    FieldMsg<M> msg;
    DdsCodec<M>::toMsg(value, msg);
    msg.serialize(out);
  }
}

/// Reads a CDR string into `value` up to its first '\0' (Fast CDR writes a string as a C
/// string, so that is all a sender can mean), without Fast CDR's temporary: no allocation when
/// `value` has the capacity. Its last character is read through Fast CDR, not jumped over:
/// Fast CDR aligns a field only when it is wider than the last one read, and after a jump the
/// last one would still be the 4-byte length (the next int, length or double was then read
/// unaligned: two one-letter strings then an int).
inline void readString(cdr::Cdr& in, std::string& value) {
  std::uint32_t length = 0;
  in >> length;
  const char* text = in.getCurrentPosition();
  if (length > 0) {
    if (!in.jump(length - 1))
      throw cdr::exception::NotEnoughMemoryException(cdr::exception::NotEnoughMemoryException::NOT_ENOUGH_MEMORY_MESSAGE_DEFAULT);
    char last = '\0';
    in >> last;
  }
  std::uint32_t size = 0;
  while (size < length && text[size] != '\0') ++size;
  value.assign(text, size);
}

template <class M>
void deserializeField(cdr::Cdr& in, M& value) {
  if constexpr (std::is_same_v<M, std::string>) {
    readString(in, value);
  } else if constexpr (std::is_same_v<M, int>) {
    std::int32_t v = 0;
    in >> v;
    value = v;
  } else if constexpr (kPrimitiveField<M>) {
    in >> value;
  } else if constexpr (core::RecordDataType<M>) {
    deserializeRecord(in, value);
  } else {
    FieldMsg<M> msg;
    msg.deserialize(in);
    DdsCodec<M>::fromMsg(msg, value);
  }
}

/// The bytes a primitive field (kPrimitiveField) takes from `alignment` on (alignment padding
/// included), as fastddsgen's code counts them; `length` is a string's characters or a sequence's
/// elements (unused for the others).
template <class M>
std::size_t primitiveSize(std::size_t length, std::size_t alignment) {
  using cdr::Cdr;
  if constexpr (std::is_same_v<M, double>) {
    return 8 + Cdr::alignment(alignment, 8);
  } else if constexpr (std::is_same_v<M, int>) {
    return 4 + Cdr::alignment(alignment, 4);
  } else if constexpr (std::is_same_v<M, bool>) {
    return 1;
  } else if constexpr (std::is_same_v<M, std::string>) {
    return 4 + Cdr::alignment(alignment, 4) + length + 1;
  } else {
    static_assert(std::is_same_v<M, std::vector<double>>, "primitiveSize: not a primitive field");
    std::size_t size = 4 + Cdr::alignment(alignment, 4);
    if (length > 0) size += length * 8 + Cdr::alignment(alignment + size, 8);
    return size;
  }
}

/// The bytes `value` takes from `alignment` on (alignment padding included), as fastddsgen's
/// getCdrSerializedSize counts them.
template <class M>
std::size_t fieldSize(const M& value, std::size_t alignment) {
  if constexpr (std::is_same_v<M, std::string> || std::is_same_v<M, std::vector<double>>) {
    return primitiveSize<M>(value.size(), alignment);
  } else if constexpr (kPrimitiveField<M>) {
    return primitiveSize<M>(0, alignment);
  } else if constexpr (core::RecordDataType<M>) {
    return recordSize(value, alignment);
  } else {
    if (messageBounded<M>()) return FieldMsg<M>::getMaxCdrSerializedSize(alignment);
    FieldMsg<M> msg;
    DdsCodec<M>::toMsg(value, msg);
    return FieldMsg<M>::getCdrSerializedSize(msg, alignment);
  }
}

/// The most bytes a field takes from `alignment` on, as fastddsgen counts them (a string of 255
/// characters, a sequence of 100 elements).
template <class M>
std::size_t fieldMaxSize(std::size_t alignment) {
  if constexpr (kPrimitiveField<M>) {
    return primitiveSize<M>(std::is_same_v<M, std::string> ? 255 : 100, alignment);
  } else if constexpr (core::RecordDataType<M>) {
    return recordMaxSize<M>(alignment);
  } else {
    return FieldMsg<M>::getMaxCdrSerializedSize(alignment);
  }
}

template <class M>
bool fieldBounded() {
  if constexpr (std::is_same_v<M, std::string> || std::is_same_v<M, std::vector<double>>)
    return false;
  else if constexpr (kPrimitiveField<M>)
    return true;
  else if constexpr (core::RecordDataType<M>)
    return recordBounded<M>();
  else
    return messageBounded<M>();
}

template <class T>
void serializeRecord(cdr::Cdr& out, const T& value) {
  core::forEachField<T>([&](const auto& f) { serializeField(out, value.*(f.member)); });
}

template <class T>
void deserializeRecord(cdr::Cdr& in, T& value) {
  core::forEachField<T>([&](const auto& f) { deserializeField(in, value.*(f.member)); });
}

template <class T>
std::size_t recordSize(const T& value, std::size_t alignment) {
  const std::size_t initial = alignment;
  core::forEachField<T>([&](const auto& f) { alignment += fieldSize(value.*(f.member), alignment); });
  return alignment - initial;
}

template <class T>
std::size_t recordMaxSize(std::size_t alignment) {
  const std::size_t initial = alignment;
  core::forEachField<T>([&](const auto& f) {
    using M = typename std::decay_t<decltype(f)>::member_type;
    alignment += fieldMaxSize<M>(alignment);
  });
  return alignment - initial;
}

template <class T>
bool recordBounded() {
  bool bounded = true;
  core::forEachField<T>([&](const auto& f) {
    using M = typename std::decay_t<decltype(f)>::member_type;
    const bool field_bounded = fieldBounded<M>();  // each asked: the first call makes its static facts
    bounded = bounded && field_bounded;
  });
  return bounded;
}

}  // namespace detail

/// The DDS type name of record `T`: "us.ProbeReading" → "us::msg::dds_::ProbeReading_" (ROS 2's
/// convention for the message ProbeReading of package us).
template <core::RecordDataType T>
std::string recordDdsTypeName() {
  static_assert(detail::validRecordName(core::DataTypeTraits<T>::name),
                "cobra: a record on DDS is named 'package.Type' (DataTypeTraits<T>::name, each part a letter then "
                "letters, digits or '_'): it travels as package::msg::dds_::Type_, ROS 2's name for that message");
  return detail::rosName(core::DataTypeTraits<T>::name, "dds_::", "_");
}

/// Fast DDS's type support of record `T`: CDR field by field (the table above), key-less.
template <core::RecordDataType T>
class RecordPubSubType final : public eprosima::fastdds::dds::TopicDataType {
 public:
  RecordPubSubType() {
    const std::string name = recordDdsTypeName<T>();
    setName(name.c_str());
    std::size_t size = detail::recordMaxSize<T>(0);
    size += detail::cdr::Cdr::alignment(size, 4);  // a possible submessage alignment, as generated code has it
    m_typeSize = static_cast<std::uint32_t>(size) + 4;  // + the encapsulation
    m_isGetKeyDefined = false;
    bounded_ = detail::recordBounded<T>();
  }

  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override {
    namespace cdr = eprosima::fastcdr;
    cdr::FastBuffer buffer(reinterpret_cast<char*>(payload->data), payload->max_size);
    cdr::Cdr out(buffer, cdr::Cdr::DEFAULT_ENDIAN, cdr::Cdr::DDS_CDR);
    payload->encapsulation = out.endianness() == cdr::Cdr::BIG_ENDIANNESS ? CDR_BE : CDR_LE;
    try {
      out.serialize_encapsulation();
      detail::serializeRecord(out, *static_cast<const T*>(data));
    } catch (const cdr::exception::Exception&) {
      return false;
    }
    payload->length = static_cast<std::uint32_t>(out.getSerializedDataLength());
    return true;
  }

  /// False, never an exception, for a payload that is not a `T` (short, a bad length, an
  /// unknown encapsulation, a boolean other than 0 or 1); `data` is then a valid `T` of
  /// unspecified value.
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    namespace cdr = eprosima::fastcdr;
    cdr::FastBuffer buffer(reinterpret_cast<char*>(payload->data), payload->length);
    cdr::Cdr in(buffer, cdr::Cdr::DEFAULT_ENDIAN, cdr::Cdr::DDS_CDR);
    try {
      in.read_encapsulation();
      payload->encapsulation = in.endianness() == cdr::Cdr::BIG_ENDIANNESS ? CDR_BE : CDR_LE;
      detail::deserializeRecord(in, *static_cast<T*>(data));
    } catch (const cdr::exception::Exception&) {
      return false;
    }
    return true;
  }

  std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override {
    return [data]() -> std::uint32_t {
      return static_cast<std::uint32_t>(detail::recordSize(*static_cast<const T*>(data), 0)) + 4u;  // + encapsulation
    };
  }

  bool getKey(void*, eprosima::fastrtps::rtps::InstanceHandle_t*, bool) override { return false; }
  void* createData() override { return new T(); }
  void deleteData(void* data) override { delete static_cast<T*>(data); }
  bool is_bounded() const override { return bounded_; }
  bool is_plain() const override { return false; }

 private:
  bool bounded_ = false;
};

}  // namespace cobra::dds
