#pragma once
/// @file
/// The IDL of a record type (core/record.hpp), for a ROS 2 package or any DDS program that
/// wants to read or write it: `idlOf<T>()`.
///
/// For "us.ProbeReading" with fields depth (double, "m"), pose (KDL.Frame) and gains (the record
/// "us.Gains"):
/// @code
/// // IDL of cobra's record us.ProbeReading (cobra::dds::idlOf): DDS type us::msg::dds_::ProbeReading_.
/// #include "geometry_msgs/msg/Pose.idl"
///
/// module us {
///   module msg {
///     // cobra record us.Gains
///     struct Gains {
///       double stiffness;  // N/m
///     };
///   };
/// };
///
/// module us {
///   module msg {
///     // cobra record us.ProbeReading
///     struct ProbeReading {
///       double depth;  // m: depth of the image below the probe
///       geometry_msgs::msg::Pose pose;
///       us::msg::Gains gains;
///     };
///   };
/// };
/// @endcode
/// One member per field, in the record's order (the CDR order of record_wire.hpp), with its unit
/// and doc as a comment; nested records are defined before use, each once; a field carried by a
/// message is that message, included by its ROS 2 path (dds/idl has cobra's). fastddsgen with
/// `-typeros2 -I <dds/idl>` compiles it into a type that serialises byte-identically
/// (dds_idl_test checks it with the code fastddsgen generates from this text).

#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "cobra/dds/codec.hpp"

namespace cobra::dds {

namespace detail {

struct IdlText {
  std::vector<std::string> includes;  // message IDL paths, in first-use order
  std::vector<std::string> defined;   // cobra names of the records written so far
  std::string body;
};

/// "geometry_msgs::msg::dds_::Pose_" → "geometry_msgs::msg::Pose".
inline std::string idlTypeOfDdsName(std::string name) {
  if (const auto at = name.find("dds_::"); at != std::string::npos) name.erase(at, 6);
  if (!name.empty() && name.back() == '_') name.pop_back();
  return name;
}

/// "geometry_msgs::msg::Pose" → "geometry_msgs/msg/Pose.idl".
inline std::string idlPathOf(std::string type) {
  for (std::size_t at = type.find("::"); at != std::string::npos; at = type.find("::", at + 1)) type.replace(at, 2, "/");
  return type + ".idl";
}

/// A comment for a field's unit and doc (line breaks as spaces), or "".
inline std::string idlComment(std::string_view unit, std::string_view doc) {
  std::string text(unit);
  if (!doc.empty()) text += (text.empty() ? "" : ": ") + std::string(doc);
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text.empty() ? text : "  // " + text;
}

template <class T>
void idlDefine(IdlText& idl);

/// The IDL type of a field of type `M`; adds what it needs (an include, a nested record) first.
template <class M>
std::string idlFieldType(IdlText& idl) {
  if constexpr (std::is_same_v<M, double>) {
    return "double";
  } else if constexpr (std::is_same_v<M, int>) {
    return "long";
  } else if constexpr (std::is_same_v<M, bool>) {
    return "boolean";
  } else if constexpr (std::is_same_v<M, std::string>) {
    return "string";
  } else if constexpr (std::is_same_v<M, std::vector<double>>) {
    return "sequence<double>";
  } else if constexpr (core::RecordDataType<M>) {
    idlDefine<M>(idl);
    return rosName(core::DataTypeTraits<M>::name, "", "");
  } else {
    typename DdsCodec<M>::PubSub support;
    std::string type = idlTypeOfDdsName(support.getName());
    std::string path = idlPathOf(type);
    bool seen = false;
    for (const auto& include : idl.includes) seen = seen || include == path;
    if (!seen) idl.includes.push_back(std::move(path));
    return type;
  }
}

/// Appends record `T`'s struct, in its modules, after the records it uses; once.
template <class T>
void idlDefine(IdlText& idl) {
  static_assert(validRecordName(core::DataTypeTraits<T>::name),
                "cobra: a record on DDS is named 'package.Type' (DataTypeTraits<T>::name, each part a letter then "
                "letters, digits or '_'): its IDL is module package { module msg { struct Type ... } }");
  const std::string_view name = core::DataTypeTraits<T>::name;
  for (const auto& done : idl.defined)
    if (done == name) return;
  idl.defined.emplace_back(name);

  std::string members;
  const std::size_t dot = name.rfind('.');
  std::vector<std::string_view> modules;
  for (std::size_t begin = 0; begin < dot;) {
    const std::size_t end = name.find('.', begin);
    modules.push_back(name.substr(begin, end - begin));
    begin = end + 1;
  }
  modules.emplace_back("msg");
  const std::string indent(2 * modules.size(), ' ');
  core::forEachField<T>([&](const auto& f) {
    using M = typename std::decay_t<decltype(f)>::member_type;
    const std::string type = idlFieldType<M>(idl);  // may define nested records first
    members += indent + "  " + type + " " + std::string(f.name) + ";" + idlComment(f.unit, f.doc) + "\n";
  });

  std::string& out = idl.body;
  out += "\n";
  for (std::size_t i = 0; i < modules.size(); ++i) out += std::string(2 * i, ' ') + "module " + std::string(modules[i]) + " {\n";
  out += indent + "// cobra record " + std::string(name) + "\n";
  out += indent + "struct " + std::string(name.substr(dot + 1)) + " {\n" + members + indent + "};\n";
  for (std::size_t i = modules.size(); i-- > 0;) out += std::string(2 * i, ' ') + "};\n";
}

}  // namespace detail

/// The IDL text of record `T` and of the records it nests (see above). Configure-time work: it
/// allocates.
template <core::RecordDataType T>
std::string idlOf() {
  detail::IdlText idl;
  detail::idlDefine<T>(idl);
  std::string text = "// IDL of cobra's record " + std::string(core::DataTypeTraits<T>::name) +
                     " (cobra::dds::idlOf): DDS type " + recordDdsTypeName<T>() + ".\n";
  for (const auto& include : idl.includes) text += "#include \"" + include + "\"\n";
  return text + idl.body;
}

}  // namespace cobra::dds
