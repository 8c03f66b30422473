#pragma once
/// @file
/// Conversions between Lua values and the registered data types (one table, by type name).
///
/// Lua forms, one per type (the same form is produced when reading and accepted when writing;
/// where a second form is accepted on input it is listed after "or"):
/// | type           | Lua form                                                             |
/// | -------------- | -------------------------------------------------------------------- |
/// | double         | a number                                                             |
/// | int            | an integral number in [-2^31, 2^31) (1.5 is refused, 2.0 accepted)   |
/// | bool           | true or false                                                        |
/// | string         | a string                                                             |
/// | vector<double> | an array of numbers {1, 2.5, 3}                                      |
/// | KDL.Vector     | {x=, y=, z=} in m, or {x, y, z}                                      |
/// | KDL.Rotation   | a unit quaternion {x=, y=, z=, w=}, or {qx, qy, qz, qw}              |
/// | KDL.Frame      | {p = <KDL.Vector>, M = <KDL.Rotation>}, or {x, y, z, qx, qy, qz, qw} |
/// | KDL.Twist      | {vel = <KDL.Vector>, rot = <KDL.Vector>} (m/s, rad/s), or 6 numbers  |
/// | KDL.Wrench     | {force = <KDL.Vector>, torque = <KDL.Vector>} (N, N·m), or 6 numbers |
/// | KDL.JntArray   | an array of joint values {q1, q2, ...}                               |
/// | Event          | {name=, source=, stamp=} with stamp in s, or just the name "e_done"  |
/// Types without an entry (registered by other modules) travel as their text form (a Lua
/// string, see `DataTypeTraits::print/parse`).

#include <any>
#include <memory>
#include <string>
#include <string_view>

#include "cobra/core/data_type.hpp"
#include "cobra/core/port.hpp"
#include "cobra/core/property.hpp"

struct lua_State;

namespace cobra::script {

class PortAccess;

/// How one registered type crosses the Lua boundary. Every function pointer is set.
struct Conversion {
  std::string_view type_name;  ///< TypeInfo::name
  std::string_view lua_form;   ///< the accepted Lua form, quoted in error messages
  /// Reads the Lua value at `index` into `out` (a value of the type). Raises no Lua error.
  /// @throws cobra::core::Error "expected <form>, got <what>" on a value of the wrong form.
  void (*read)(lua_State* L, int index, std::any& out);
  /// Pushes `value` (holding the type). A Lua memory error is caught and thrown as
  /// cobra::core::Error naming the pool; nothing else is thrown.
  void (*push)(lua_State* L, const std::any& value);
  /// The value of `property` (of this type) and setting it (Property::set: checked, applied
  /// between two updates).
  std::any (*get_property)(const core::PropertyBase& property);
  void (*set_property)(core::PropertyBase& property, const std::any& value);
  /// A reader/writer of `port` (of this type) that allocates nothing per call once made.
  std::unique_ptr<PortAccess> (*access)(core::PortBase& port);
  /// A new port or property of this type (for script-defined components).
  std::unique_ptr<core::PortBase> (*make_port)(core::PortDirection direction, std::string name, std::string doc,
                                               std::string unit);
  std::unique_ptr<core::PropertyBase> (*make_property)(std::string name, const std::any& initial, std::string unit,
                                                       std::string doc);
};

/// The conversion of `type`, or nullptr when it has none (use the text form then).
const Conversion* findConversion(const core::TypeInfo& type);
/// By type name ("double", "KDL.Frame"), or nullptr.
const Conversion* findConversion(std::string_view type_name);
/// Names of every type with a conversion, comma-separated (for error messages).
std::string conversionNames();

/// "the number 1.5", "a table", "the string \"abc\"": what a Lua value is, for messages.
std::string describeLuaValue(lua_State* L, int index);

}  // namespace cobra::script
