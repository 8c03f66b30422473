#pragma once
/// @file
/// The type registry: every port and property type has a name and a data kind (ARCHITECTURE §2).
///
/// A type becomes usable on a port or property by specialising `DataTypeTraits<T>` with a
/// `name`, a `kind`, and `print`/`parse` functions. Using an unregistered type is a compile
/// error that says so (see `RegisteredDataType`), so a typo cannot silently create a new type.

#include <array>
#include <chrono>
#include <cstddef>
#include <span>
#include <string>
#include <tuple>
#include <type_traits>
#include <string_view>
#include <typeindex>
#include <vector>

#include "cobra/core/event.hpp"

namespace KDL {
class Vector;
class Rotation;
class Frame;
class Twist;
class Wrench;
class JntArray;
}  // namespace KDL

namespace cobra::core {

/// Pure data is numbers and geometry; logic data is events and state names. Component roles
/// (Calculation, Supervision, Decision, Bridge) are checked against this classification.
enum class DataKind { Pure, Logic };

std::string_view toString(DataKind kind);

/// Specialise for each type that travels on a port or is held in a property:
/// @code
/// template <> struct DataTypeTraits<MyType> {
///   static constexpr std::string_view name = "my::Type";
///   static constexpr DataKind kind = DataKind::Pure;
///   static std::string print(const MyType& value);
///   static bool parse(std::string_view text, MyType& out);  // false when `text` is not a MyType
///   static constexpr std::string_view format = "how the text form looks, for error messages";
///   // Optional, for the editor's component generator and listings:
///   static constexpr std::string_view cpp = "my::Type";          // the C++ spelling
///   static constexpr std::string_view header = "<my/type.hpp>";  // the header declaring it
///   static constexpr std::string_view unit = "m";                // the usual unit of a port of it
/// };
/// @endcode
/// A struct of named fields is better registered as a record (record.hpp: `RecordTraits`): its
/// text form, Lua value, CSV columns and the rest are then derived from its fields.
/// The capabilities beyond text (Lua, CSV, DDS) are codecs of the modules that own them, found at
/// compile time; `cobra::types::registerType<T>()` (types/) registers a type with all of them.
template <class T>
struct DataTypeTraits;

template <class T>
concept RegisteredDataType = requires(const T& value, std::string_view text, T& out) {
  { DataTypeTraits<T>::name } -> std::convertible_to<std::string_view>;
  { DataTypeTraits<T>::kind } -> std::convertible_to<DataKind>;
  { DataTypeTraits<T>::format } -> std::convertible_to<std::string_view>;
  { DataTypeTraits<T>::print(value) } -> std::same_as<std::string>;
  { DataTypeTraits<T>::parse(text, out) } -> std::same_as<bool>;
};

struct TypeInfo;

/// One field of a record type, at run time (for the editor, the studio and the console).
struct FieldInfo {
  std::string_view name;  ///< a Lua identifier; the CSV column suffix
  std::string_view unit;  ///< SI unit, "" when the field's type says it
  std::string_view doc;
  const TypeInfo* type;   ///< the field's registered type
};

/// Run-time description of a registered type, shared by every port and property of that type.
struct TypeInfo {
  std::string_view name;
  DataKind kind;
  std::type_index id;
  std::string_view format;  ///< text form accepted by parse, quoted in error messages
  std::string_view cpp{};     ///< C++ spelling ("KDL::Frame"), "" when the traits give none
  std::string_view header{};  ///< header declaring it ("<kdl/frames.hpp>"), "" for none needed
  std::string_view unit{};    ///< the usual unit of a port of this type ("m"), may be ""
  std::span<const FieldInfo> fields{};  ///< a record's fields in order; empty for other types
};

/// Name lookup and listing of the registered types (for the deployer, console and studio).
class TypeRegistry {
 public:
  /// The type called `name`, or nullptr. The built-in types are always present.
  static const TypeInfo* find(std::string_view name);
  /// Every type registered so far, sorted by name.
  static std::vector<const TypeInfo*> all();
  /// Adds `info`; called once per type by `typeInfo<T>()` (once per shared library using it).
  /// @throws Error naming the name and both C++ types when another type has `info.name`.
  static void add(const TypeInfo& info);
};

template <class T>
const TypeInfo& typeInfo();

namespace data_type_detail {
template <class T>
std::string_view optionalCpp() {
  if constexpr (requires { DataTypeTraits<T>::cpp; }) return DataTypeTraits<T>::cpp;
  else return {};
}
template <class T>
std::string_view optionalHeader() {
  if constexpr (requires { DataTypeTraits<T>::header; }) return DataTypeTraits<T>::header;
  else return {};
}
template <class T>
std::string_view optionalUnit() {
  if constexpr (requires { DataTypeTraits<T>::unit; }) return DataTypeTraits<T>::unit;
  else return {};
}
/// The run-time field list of a record (`DataTypeTraits<T>::fields`, see record.hpp); empty otherwise.
template <class T>
std::span<const FieldInfo> fieldInfos() {
  if constexpr (requires { std::tuple_size<std::decay_t<decltype(DataTypeTraits<T>::fields)>>::value; }) {
    static const auto infos = std::apply(
        [](const auto&... f) {
          return std::array<FieldInfo, sizeof...(f)>{
              FieldInfo{f.name, f.unit, f.doc, &typeInfo<typename std::decay_t<decltype(f)>::member_type>()}...};
        },
        DataTypeTraits<T>::fields);
    return infos;
  } else {
    return {};
  }
}
}  // namespace data_type_detail

/// The registry entry of `T`, registered on first use (a record's field types with it).
template <class T>
const TypeInfo& typeInfo() {
  static_assert(RegisteredDataType<T>,
                "cobra: this type is not registered for ports and properties; specialise "
                "cobra::core::DataTypeTraits<T> with name, kind, format, print and parse");
  static const TypeInfo info = [] {
    TypeInfo i{DataTypeTraits<T>::name,
               DataTypeTraits<T>::kind,
               std::type_index(typeid(T)),
               DataTypeTraits<T>::format,
               data_type_detail::optionalCpp<T>(),
               data_type_detail::optionalHeader<T>(),
               data_type_detail::optionalUnit<T>(),
               data_type_detail::fieldInfos<T>()};
    TypeRegistry::add(i);
    return i;
  }();
  return info;
}

#define COBRA_DECLARE_BUILTIN_TRAITS_(Type, Name, Kind, Format, Cpp, Header, Unit) \
  template <>                                                                     \
  struct DataTypeTraits<Type> {                                                   \
    static constexpr std::string_view name = Name;                                \
    static constexpr DataKind kind = DataKind::Kind;                              \
    static constexpr std::string_view format = Format;                            \
    static constexpr std::string_view cpp = Cpp;                                  \
    static constexpr std::string_view header = Header;                            \
    static constexpr std::string_view unit = Unit;                                \
    static std::string print(const Type& value);                                  \
    static bool parse(std::string_view text, Type& out);                          \
  }

COBRA_DECLARE_BUILTIN_TRAITS_(double, "double", Pure, "a number, e.g. 1.5", "double", "", "1");
COBRA_DECLARE_BUILTIN_TRAITS_(int, "int", Pure, "an integer, e.g. 3", "int", "", "1");
COBRA_DECLARE_BUILTIN_TRAITS_(bool, "bool", Pure, "true or false", "bool", "", "");
COBRA_DECLARE_BUILTIN_TRAITS_(std::string, "string", Pure, "any text", "std::string", "<string>", "");
COBRA_DECLARE_BUILTIN_TRAITS_(std::vector<double>, "vector<double>", Pure, "a list of numbers, e.g. [1, 2.5, 3]",
                              "std::vector<double>", "<vector>", "1");
COBRA_DECLARE_BUILTIN_TRAITS_(KDL::Vector, "KDL.Vector", Pure, "[x, y, z] in m", "KDL::Vector", "<kdl/frames.hpp>", "m");
COBRA_DECLARE_BUILTIN_TRAITS_(KDL::Rotation, "KDL.Rotation", Pure, "a unit quaternion [qx, qy, qz, qw]", "KDL::Rotation",
                              "<kdl/frames.hpp>", "1");
COBRA_DECLARE_BUILTIN_TRAITS_(KDL::Frame, "KDL.Frame", Pure, "[x, y, z, qx, qy, qz, qw] (m, unit quaternion)", "KDL::Frame",
                              "<kdl/frames.hpp>", "m");
COBRA_DECLARE_BUILTIN_TRAITS_(KDL::Twist, "KDL.Twist", Pure, "[vx, vy, vz, wx, wy, wz] in m/s and rad/s", "KDL::Twist",
                              "<kdl/frames.hpp>", "m/s, rad/s");
COBRA_DECLARE_BUILTIN_TRAITS_(KDL::Wrench, "KDL.Wrench", Pure, "[fx, fy, fz, tx, ty, tz] in N and N·m", "KDL::Wrench",
                              "<kdl/frames.hpp>", "N, N·m");
COBRA_DECLARE_BUILTIN_TRAITS_(KDL::JntArray, "KDL.JntArray", Pure, "a list of joint values, e.g. [0, 0.5, 1.2]",
                              "KDL::JntArray", "<kdl/jntarray.hpp>", "rad");
COBRA_DECLARE_BUILTIN_TRAITS_(Event, "Event", Logic, "an event name, e.g. e_done", "cobra::core::Event", "", "");
COBRA_DECLARE_BUILTIN_TRAITS_(TaskState, "TaskState", Logic, "a state path, e.g. root.on.moving", "cobra::core::TaskState",
                              "", "");

#undef COBRA_DECLARE_BUILTIN_TRAITS_

/// A list of types, walked with `forEachType`.
template <class... T>
struct TypeList {};

/// Calls `f(std::type_identity<T>{})` for each T of the list, in order.
template <class... T, class F>
void forEachType(TypeList<T...>, F&& f) {
  (f(std::type_identity<T>{}), ...);
}

/// cobra's own data types, declared above: the one list of them. The registry holds them from
/// the start; the capability registries (Lua in script, CSV in reporting, DDS) seed themselves
/// from this list at their first use, so no program has to register them, and the types module
/// (`cobra::types::registerBuiltins`) goes through it too. A package's types are registered by
/// the package (`cobra::types::registerType<T>()`), never added here.
using BuiltinDataTypes = TypeList<double, int, bool, std::string, std::vector<double>, KDL::Vector, KDL::Rotation,
                                  KDL::Frame, KDL::Twist, KDL::Wrench, KDL::JntArray, Event, TaskState>;

/// Human-readable text of a value of a registered type.
template <RegisteredDataType T>
std::string printValue(const T& value) {
  return DataTypeTraits<T>::print(value);
}

}  // namespace cobra::core
