#pragma once
/// @file
/// How a C++ value crosses the Lua boundary: `LuaCodec<T>`, found at compile time.
///
/// A codec reads the Lua value at a stack index into a T and pushes a T:
/// @code
/// template <> struct cobra::script::LuaCodec<MyType> {
///   static std::string_view form();                            // "a table {a=, b=}", for messages
///   static void read(lua_State* L, int index, MyType& out);    // throws, raises no Lua error
///   static void push(lua_State* L, const MyType& value);       // may raise a Lua (memory) error
/// };
/// @endcode
/// - `read` throws cobra::core::Error "expected <form>, got <what>" (`lua_codec::refuse`) on a
///   value of the wrong form and never raises a Lua error; it may leave `out` half written then.
///   It pushes only through functions that cannot raise (use `lua_codec::pushRawField`).
/// - `push` pushes exactly one value. It is called in protected mode (a memory error of the
///   state's pool becomes an exception in the caller), so it must hold no C++ object with a
///   destructor: Debian's Lua is C and unwinds with longjmp.
///
/// cobra's own types have leaf codecs (declared below, defined in script/src/convert.cpp); every
/// record type (core/record.hpp) has one derived from its fields: a table with one entry per
/// field, each read and pushed by its own field type's codec. Any other type fails to compile
/// with the static_assert below, naming the type in the instantiation trace.
///
/// Lua forms of cobra's own types (the same form is produced when reading and accepted when
/// writing; where a second form is accepted on input it is listed after "or"):
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
/// | TaskState      | the state path as a string "root.on.moving"                          |
/// | a record       | {field1 = <its form>, field2 = ...}: every field, no other key       |

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>

#include "cobra/core/data_type.hpp"
#include "cobra/core/error.hpp"
#include "cobra/core/record.hpp"

struct lua_State;

namespace cobra::script {

template <class T>
inline constexpr bool kNoLuaCodec = false;

/// The Lua codec of `T`. Not defined for a type that is neither one of cobra's own nor a record.
template <class T>
struct LuaCodec {
  static_assert(kNoLuaCodec<T>,
                "cobra: no Lua form for this type: make it a record (DataTypeTraits<T> : RecordTraits<T> with "
                "fields) or specialise cobra::script::LuaCodec<T>");
};

/// Lua stack primitives for codecs written in headers (this header does not include lua.h).
namespace lua_codec {
/// Throws cobra::core::Error "expected <form>, got <what the value at index is>[ (<detail>)]".
[[noreturn]] void refuse(lua_State* L, int index, std::string_view form, std::string_view detail = {});
bool isTable(lua_State* L, int index);
int absIndex(lua_State* L, int index);
int top(lua_State* L);
void setTop(lua_State* L, int top);
/// Pushes t[key] of the table at `index`, or nil; raises nothing (no metamethod, no new string).
void pushRawField(lua_State* L, int index, std::string_view key);
/// The first key of the table at `index` that is not a string among `names` (as a description:
/// "'stifness'", "the integer 1"), or "" when every key is one of them. Raises nothing.
std::string unknownKey(lua_State* L, int index, std::span<const std::string_view> names);
/// Pushes a new table with room for `fields` named fields. Raises on memory: protected mode only.
void newTable(lua_State* L, int fields);
/// t[name] = the value on top, for the table just below it; pops the value. Protected mode only.
void setField(lua_State* L, std::string_view name);
void pushNil(lua_State* L);
/// Runs `push(L, value)` in protected mode: a Lua error becomes cobra::core::Error.
void pushProtected(lua_State* L, void (*push)(lua_State*, const void*), const void* value);

/// Restores the stack top when it goes out of scope (also when a read throws).
class StackGuard {
 public:
  explicit StackGuard(lua_State* L) : L_(L), top_(top(L)) {}
  ~StackGuard() { setTop(L_, top_); }
  StackGuard(const StackGuard&) = delete;
  StackGuard& operator=(const StackGuard&) = delete;

 private:
  lua_State* L_;
  int top_;
};

/// A refusal inside a record's field: carries the dotted field path ("gains.stiffness") so that
/// the message names the field however deeply it is nested.
class FieldError : public core::Error {
 public:
  FieldError(std::string path, std::string detail)
      : core::Error("field '" + path + "': " + detail), path_(std::move(path)), detail_(std::move(detail)) {}
  const std::string& path() const { return path_; }
  const std::string& detail() const { return detail_; }

 private:
  std::string path_;
  std::string detail_;
};
}  // namespace lua_codec

#define COBRA_DECLARE_LUA_CODEC_(Type)                       \
  template <>                                                \
  struct LuaCodec<Type> {                                    \
    static std::string_view form();                          \
    static void read(lua_State* L, int index, Type& out);    \
    static void push(lua_State* L, const Type& value);       \
  }

COBRA_DECLARE_LUA_CODEC_(double);
COBRA_DECLARE_LUA_CODEC_(int);
COBRA_DECLARE_LUA_CODEC_(bool);
COBRA_DECLARE_LUA_CODEC_(std::string);
COBRA_DECLARE_LUA_CODEC_(std::vector<double>);
COBRA_DECLARE_LUA_CODEC_(KDL::Vector);
COBRA_DECLARE_LUA_CODEC_(KDL::Rotation);
COBRA_DECLARE_LUA_CODEC_(KDL::Frame);
COBRA_DECLARE_LUA_CODEC_(KDL::Twist);
COBRA_DECLARE_LUA_CODEC_(KDL::Wrench);
COBRA_DECLARE_LUA_CODEC_(KDL::JntArray);
COBRA_DECLARE_LUA_CODEC_(core::Event);
COBRA_DECLARE_LUA_CODEC_(core::TaskState);

#undef COBRA_DECLARE_LUA_CODEC_

/// Every record: a table with one entry per field, each by its field type's codec.
template <core::RecordDataType T>
struct LuaCodec<T> {
  /// "a table {depth=, label=, pose=} (us.ProbeReading)".
  static std::string_view form() {
    static const std::string text = [] {
      std::string t = "a table {";
      core::forEachField<T>([&](const auto& f) {
        t += (t.back() == '{' ? "" : ", ");
        t += f.name;
        t += "=";
      });
      return t + "} (" + std::string(core::DataTypeTraits<T>::name) + ")";
    }();
    return text;
  }

  /// Every field must be present and no other key: a typo is refused, not ignored.
  /// @throws lua_codec::FieldError naming the field for a field of the wrong form.
  static void read(lua_State* L, int index, T& out) {
    index = lua_codec::absIndex(L, index);
    if (!lua_codec::isTable(L, index)) lua_codec::refuse(L, index, form());
    if (const std::string key = lua_codec::unknownKey(L, index, names()); !key.empty())
      lua_codec::refuse(L, index, form(), std::string(core::DataTypeTraits<T>::name) + " has no field " + key);
    core::forEachField<T>([&](const auto& f) {
      using M = typename std::decay_t<decltype(f)>::member_type;
      lua_codec::StackGuard guard(L);
      lua_codec::pushRawField(L, index, f.name);
      try {
        LuaCodec<M>::read(L, lua_codec::top(L), out.*(f.member));
      } catch (const lua_codec::FieldError& e) {
        throw lua_codec::FieldError(std::string(f.name) + "." + e.path(), e.detail());
      } catch (const core::Error& e) {
        throw lua_codec::FieldError(std::string(f.name), e.what());
      }
    });
  }

  static void push(lua_State* L, const T& value) {
    lua_codec::newTable(L, static_cast<int>(core::fieldCount<T>()));
    core::forEachField<T>([&](const auto& f) {
      using M = typename std::decay_t<decltype(f)>::member_type;
      LuaCodec<M>::push(L, value.*(f.member));
      lua_codec::setField(L, f.name);
    });
  }

 private:
  static std::span<const std::string_view> names() {
    static const auto list = std::apply([](const auto&... f) { return std::array<std::string_view, sizeof...(f)>{f.name...}; },
                                        core::DataTypeTraits<T>::fields);
    return list;
  }
};

}  // namespace cobra::script
