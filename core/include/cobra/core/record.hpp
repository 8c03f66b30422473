#pragma once
/// @file
/// Record types: a user's struct of named fields, each of a registered type, with its SI unit.
///
/// A record is registered once, next to its definition, by listing its fields; every capability
/// (text, Lua value, CSV columns, DDS wire type and IDL, studio series) is derived from the field
/// list by the module that owns the capability, so a package's type travels everywhere cobra's
/// own types do (ARCHITECTURE §2):
/// @code
/// struct ProbeReading {
///   double depth = 0.0;    // m
///   double gain = 1.0;     // 1
///   KDL::Frame pose;       // m, unit quaternion
/// };
/// template <>
/// struct cobra::core::DataTypeTraits<ProbeReading> : cobra::core::RecordTraits<ProbeReading> {
///   static constexpr std::string_view name = "us.ProbeReading";
///   static constexpr auto fields = std::tuple{
///       cobra::core::field("depth", &ProbeReading::depth, "m", "depth of the image below the probe"),
///       cobra::core::field("gain", &ProbeReading::gain, "1"),
///       cobra::core::field("pose", &ProbeReading::pose, "m, quaternion")};
/// };
/// @endcode
/// The record's kind is pure data unless the traits say otherwise (`kind`), its text form is
/// `{depth = 0.05, gain = 1, pose = [0, 0, 0.1, 0, 0, 0, 1]}` (fields in any order on input, each
/// exactly once; string fields in double quotes). A field of a type that is not registered fails
/// to compile naming `DataTypeTraits<member type>`.

#include <cstddef>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "cobra/core/data_type.hpp"

namespace cobra::core {

/// One field of a record type: its name, the member it reads, its SI unit and a line of doc.
template <class Record, class Member>
struct Field {
  using record_type = Record;
  using member_type = Member;
  std::string_view name;   ///< a Lua identifier: letters, digits, '_' (also the CSV column suffix)
  Member Record::*member;  ///< the data member
  std::string_view unit;   ///< SI unit ("m", "rad", "N", "1" for a ratio); "" when the field's type says it
  std::string_view doc;    ///< one line for the editor, console and generated IDL
};

/// A field of `Record`: `field("depth", &ProbeReading::depth, "m", "what it is")`.
template <class Record, class Member>
constexpr Field<Record, Member> field(std::string_view name, Member Record::*member, std::string_view unit = "",
                                      std::string_view doc = "") {
  return Field<Record, Member>{name, member, unit, doc};
}

/// A registered type described by its fields (`DataTypeTraits<T>::fields`, a tuple of Field).
template <class T>
concept RecordDataType = requires { std::tuple_size<std::decay_t<decltype(DataTypeTraits<T>::fields)>>::value; };

/// Calls `f(field)` for each field of record `T`, in declaration order.
template <class T, class F>
constexpr void forEachField(F&& f) {
  std::apply([&](const auto&... each) { (f(each), ...); }, DataTypeTraits<T>::fields);
}

/// The number of fields of record `T`.
template <class T>
constexpr std::size_t fieldCount() {
  return std::tuple_size_v<std::decay_t<decltype(DataTypeTraits<T>::fields)>>;
}

namespace record_detail {
/// Splits "{a = 1, b = [1, 2], c = {x = 1}}" into (name, value text) pairs at the top level
/// (brackets, braces and double-quoted strings nest). False when the text is not such a record.
bool split(std::string_view text, std::vector<std::pair<std::string_view, std::string_view>>& items);
/// `text` in double quotes, with '"' and '\' escaped by '\'.
std::string quote(std::string_view text);
/// The text inside double quotes, unescaped; false when `text` is not one quoted string.
bool unquote(std::string_view text, std::string& out);
}  // namespace record_detail

/// The text codec of a record, derived from its fields: inherit it in `DataTypeTraits<T>`.
template <class T>
struct RecordTraits {
  static constexpr DataKind kind = DataKind::Pure;
  static constexpr std::string_view format = "a record {field = value, ...} with every field of the type once";

  static std::string print(const T& value) {
    std::string text = "{";
    forEachField<T>([&](const auto& f) {
      using M = typename std::decay_t<decltype(f)>::member_type;
      static_assert(RegisteredDataType<M>,
                    "cobra: a record field's type is not registered; specialise "
                    "cobra::core::DataTypeTraits for the member's type (or make it a record too)");
      if (text.size() > 1) text += ", ";
      text += f.name;
      text += " = ";
      if constexpr (std::is_same_v<M, std::string>)
        text += record_detail::quote(value.*(f.member));
      else
        text += DataTypeTraits<M>::print(value.*(f.member));
    });
    return text + "}";
  }

  /// Every field exactly once, in any order; `out` is unchanged when the text is not a `T`.
  static bool parse(std::string_view text, T& out) {
    std::vector<std::pair<std::string_view, std::string_view>> items;
    if (!record_detail::split(text, items) || items.size() != fieldCount<T>()) return false;
    T value = out;
    bool ok = true;
    forEachField<T>([&](const auto& f) {
      using M = typename std::decay_t<decltype(f)>::member_type;
      std::size_t seen = 0;
      for (const auto& [name, item] : items) {
        if (name != f.name) continue;
        ++seen;
        if constexpr (std::is_same_v<M, std::string>)
          ok = ok && record_detail::unquote(item, value.*(f.member));
        else
          ok = ok && DataTypeTraits<M>::parse(item, value.*(f.member));
      }
      ok = ok && seen == 1;
    });
    if (ok) out = std::move(value);
    return ok;
  }
};

}  // namespace cobra::core
