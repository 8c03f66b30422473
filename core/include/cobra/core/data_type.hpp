#pragma once
/// @file
/// The type registry: every port and property type has a name and a data kind (ARCHITECTURE §2).
///
/// A type becomes usable on a port or property by specialising `DataTypeTraits<T>` with a
/// `name`, a `kind`, and `print`/`parse` functions. Using an unregistered type is a compile
/// error that says so (see `RegisteredDataType`), so a typo cannot silently create a new type.

#include <chrono>
#include <string>
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
/// };
/// @endcode
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

/// Run-time description of a registered type, shared by every port and property of that type.
struct TypeInfo {
  std::string_view name;
  DataKind kind;
  std::type_index id;
  std::string_view format;  ///< text form accepted by parse, quoted in error messages
};

/// Name lookup and listing of the registered types (for the deployer, console and studio).
class TypeRegistry {
 public:
  /// The type called `name`, or nullptr. The built-in types are always present.
  static const TypeInfo* find(std::string_view name);
  /// Every type registered so far, sorted by name.
  static std::vector<const TypeInfo*> all();
  /// Adds `info`; called once per type by `typeInfo<T>()`.
  static void add(const TypeInfo& info);
};

/// The registry entry of `T`, registered on first use.
template <class T>
const TypeInfo& typeInfo() {
  static_assert(RegisteredDataType<T>,
                "cobra: this type is not registered for ports and properties; specialise "
                "cobra::core::DataTypeTraits<T> with name, kind, format, print and parse");
  static const TypeInfo info = [] {
    TypeInfo i{DataTypeTraits<T>::name, DataTypeTraits<T>::kind, std::type_index(typeid(T)),
               DataTypeTraits<T>::format};
    TypeRegistry::add(i);
    return i;
  }();
  return info;
}

#define COBRA_DECLARE_BUILTIN_TRAITS_(Type, Name, Kind, Format)    \
  template <>                                                       \
  struct DataTypeTraits<Type> {                                     \
    static constexpr std::string_view name = Name;                  \
    static constexpr DataKind kind = DataKind::Kind;                \
    static constexpr std::string_view format = Format;              \
    static std::string print(const Type& value);                    \
    static bool parse(std::string_view text, Type& out);            \
  }

COBRA_DECLARE_BUILTIN_TRAITS_(double, "double", Pure, "a number, e.g. 1.5");
COBRA_DECLARE_BUILTIN_TRAITS_(int, "int", Pure, "an integer, e.g. 3");
COBRA_DECLARE_BUILTIN_TRAITS_(bool, "bool", Pure, "true or false");
COBRA_DECLARE_BUILTIN_TRAITS_(std::string, "string", Pure, "any text");
COBRA_DECLARE_BUILTIN_TRAITS_(std::vector<double>, "vector<double>", Pure, "a list of numbers, e.g. [1, 2.5, 3]");
COBRA_DECLARE_BUILTIN_TRAITS_(KDL::Vector, "KDL.Vector", Pure, "[x, y, z] in m");
COBRA_DECLARE_BUILTIN_TRAITS_(KDL::Rotation, "KDL.Rotation", Pure, "a unit quaternion [qx, qy, qz, qw]");
COBRA_DECLARE_BUILTIN_TRAITS_(KDL::Frame, "KDL.Frame", Pure, "[x, y, z, qx, qy, qz, qw] (m, unit quaternion)");
COBRA_DECLARE_BUILTIN_TRAITS_(KDL::Twist, "KDL.Twist", Pure, "[vx, vy, vz, wx, wy, wz] in m/s and rad/s");
COBRA_DECLARE_BUILTIN_TRAITS_(KDL::Wrench, "KDL.Wrench", Pure, "[fx, fy, fz, tx, ty, tz] in N and N·m");
COBRA_DECLARE_BUILTIN_TRAITS_(KDL::JntArray, "KDL.JntArray", Pure, "a list of joint values, e.g. [0, 0.5, 1.2]");
COBRA_DECLARE_BUILTIN_TRAITS_(Event, "Event", Logic, "an event name, e.g. e_done");
COBRA_DECLARE_BUILTIN_TRAITS_(TaskState, "TaskState", Logic, "a state path, e.g. root.on.moving");

#undef COBRA_DECLARE_BUILTIN_TRAITS_

/// Human-readable text of a value of a registered type.
template <RegisteredDataType T>
std::string printValue(const T& value) {
  return DataTypeTraits<T>::print(value);
}

}  // namespace cobra::core
