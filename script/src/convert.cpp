// The Lua codecs of cobra's own types, the Lua primitives the header codecs use, and the registry of
// conversions (filled by registerLuaType<T>; cobra's own types from core::BuiltinDataTypes).

#include "cobra/script/convert.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/core/activity.hpp"
#include "cobra/core/component.hpp"
#include "cobra/core/event.hpp"
#include "lua_guard.hpp"
#include "cobra/script/port_access.hpp"

namespace cobra::script {

std::string describeLuaValue(lua_State* L, int index) {
  switch (lua_type(L, index)) {
    case LUA_TNIL: return "nil";
    case LUA_TBOOLEAN: return lua_toboolean(L, index) ? "the boolean true" : "the boolean false";
    case LUA_TNUMBER:
      if (lua_isinteger(L, index)) return "the integer " + std::to_string(lua_tointeger(L, index));
      return "the number " + core::printValue(static_cast<double>(lua_tonumber(L, index)));
    case LUA_TSTRING: {
      std::size_t n = 0;
      const char* s = lua_tolstring(L, index, &n);
      return "the string \"" + (n > 40 ? std::string(s, 40) + "..." : std::string(s, n)) + "\"";
    }
    case LUA_TTABLE: return "a table";
    default: return std::string("a ") + lua_typename(L, lua_type(L, index));
  }
}

namespace lua_codec {

void refuse(lua_State* L, int index, std::string_view form, std::string_view detail) {
  throw core::Error("expected " + std::string(form) + ", got " + describeLuaValue(L, index) +
                    (detail.empty() ? "" : " (" + std::string(detail) + ")"));
}
bool isTable(lua_State* L, int index) { return lua_type(L, index) == LUA_TTABLE; }
int absIndex(lua_State* L, int index) { return lua_absindex(L, index); }
int top(lua_State* L) { return lua_gettop(L); }
void setTop(lua_State* L, int top) { lua_settop(L, top); }
void pushRawField(lua_State* L, int index, std::string_view key) { detail::rawField(L, index, key); }
void pushNil(lua_State* L) { lua_pushnil(L); }

std::string unknownKey(lua_State* L, int index, std::span<const std::string_view> names) {
  index = lua_absindex(L, index);
  StackGuard guard(L);
  lua_pushnil(L);
  while (lua_next(L, index) != 0) {
    if (lua_type(L, -2) != LUA_TSTRING) return describeLuaValue(L, -2);
    std::size_t n = 0;
    const char* k = lua_tolstring(L, -2, &n);
    if (std::find(names.begin(), names.end(), std::string_view(k, n)) == names.end())
      return "'" + std::string(k, n) + "'";
    lua_pop(L, 1);
  }
  return {};
}

void newTable(lua_State* L, int fields) { lua_createtable(L, 0, fields); }
void setField(lua_State* L, std::string_view name) {
  lua_pushlstring(L, name.data(), name.size());
  lua_insert(L, -2);
  lua_rawset(L, -3);
}

namespace {
struct PushJob {
  void (*push)(lua_State*, const void*);
  const void* value;
};
int pushThunk(lua_State* L) {
  const auto* job = static_cast<const PushJob*>(lua_touserdata(L, 1));
  job->push(L, job->value);
  return 1;
}
}  // namespace

void pushProtected(lua_State* L, void (*push)(lua_State*, const void*), const void* value) {
  const PushJob job{push, value};
  detail::protectedCall(L, &pushThunk, &job, 1);
}

}  // namespace lua_codec

namespace {

using lua_codec::refuse;
using lua_codec::StackGuard;

/// Reads the array {a, b, ...} of exactly `count` numbers at `index`.
void readArray(lua_State* L, int index, double* out, std::size_t count, std::string_view form) {
  StackGuard guard(L);
  index = lua_absindex(L, index);
  for (std::size_t i = 0; i < count; ++i) {
    if (lua_rawgeti(L, index, static_cast<lua_Integer>(i + 1)) != LUA_TNUMBER) {
      const std::string what = "element " + std::to_string(i + 1) + " is " + describeLuaValue(L, -1);
      refuse(L, index, form, what);
    }
    out[i] = static_cast<double>(lua_tonumber(L, -1));
    lua_pop(L, 1);
  }
}

/// Reads the number fields `names` of the record at `index`.
template <std::size_t N>
void readFields(lua_State* L, int index, double* out, const std::array<std::string_view, N>& names,
                std::string_view form) {
  StackGuard guard(L);
  index = lua_absindex(L, index);
  for (std::size_t i = 0; i < N; ++i) {
    detail::rawField(L, index, names[i]);
    if (lua_type(L, -1) != LUA_TNUMBER) {
      const std::string what = "field '" + std::string(names[i]) + "' is " + describeLuaValue(L, -1);
      refuse(L, index, form, what);
    }
    out[i] = static_cast<double>(lua_tonumber(L, -1));
    lua_pop(L, 1);
  }
}

void pushFields(lua_State* L, const double* values, std::initializer_list<const char*> names) {
  lua_createtable(L, 0, static_cast<int>(names.size()));
  std::size_t i = 0;
  for (const char* name : names) {
    lua_pushnumber(L, values[i++]);
    lua_setfield(L, -2, name);
  }
}

void pushArray(lua_State* L, const double* values, std::size_t count) {
  lua_createtable(L, static_cast<int>(count), 0);
  for (std::size_t i = 0; i < count; ++i) {
    lua_pushnumber(L, values[i]);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
}

constexpr std::string_view kVectorForm = "{x=, y=, z=} (m) or {x, y, z}";
constexpr std::string_view kRotationForm = "a unit quaternion {x=, y=, z=, w=} or {qx, qy, qz, qw}";
constexpr std::string_view kFrameForm = "{p = {x=, y=, z=}, M = {x=, y=, z=, w=}} or {x, y, z, qx, qy, qz, qw}";
constexpr std::string_view kTwistForm = "{vel = {x=, y=, z=}, rot = {x=, y=, z=}} (m/s, rad/s) or {vx, vy, vz, wx, wy, wz}";
constexpr std::string_view kWrenchForm = "{force = {x=, y=, z=}, torque = {x=, y=, z=}} (N, N·m) or {fx, fy, fz, tx, ty, tz}";
constexpr std::string_view kEventForm = "an event name \"e_done\" or {name=, source=, stamp=} (stamp in s)";

/// True when the table at `index` is an array of exactly `count` elements; false when it has
/// no array part (a record); refuses anything else.
bool isArrayOf(lua_State* L, int index, std::size_t count, std::string_view form) {
  if (lua_type(L, index) != LUA_TTABLE) refuse(L, index, form);
  const auto n = static_cast<std::size_t>(lua_rawlen(L, index));
  if (n == 0) return false;
  if (n != count) refuse(L, index, form, "an array of " + std::to_string(n) + " elements");
  return true;
}

void readVector(lua_State* L, int index, KDL::Vector& out, std::string_view form = kVectorForm) {
  if (isArrayOf(L, index, 3, form)) readArray(L, index, out.data, 3, form);
  else readFields<3>(L, index, out.data, {"x", "y", "z"}, form);
}

void readRotation(lua_State* L, int index, KDL::Rotation& out, std::string_view form = kRotationForm) {
  double q[4];
  if (isArrayOf(L, index, 4, form)) readArray(L, index, q, 4, form);
  else readFields<4>(L, index, q, {"x", "y", "z", "w"}, form);
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  // The same tolerance as the text form: a quaternion that is not unit is a typo.
  if (!(std::abs(norm - 1.0) <= 1e-6)) refuse(L, index, form, "its norm is " + core::printValue(norm) + ", not 1");
  out = KDL::Rotation::Quaternion(q[0], q[1], q[2], q[3]);
}

/// Reads the sub-record `name` of the record at `index` with `read`.
template <class V, class F>
void readMember(lua_State* L, int index, std::string_view name, V& out, std::string_view form, F read) {
  StackGuard guard(L);
  index = lua_absindex(L, index);
  detail::rawField(L, index, name);
  if (lua_type(L, -1) != LUA_TTABLE) refuse(L, index, form, "field '" + std::string(name) + "' is " + describeLuaValue(L, -1));
  read(L, -1, out, form);
}

/// Twist and Wrench: a record of two named vectors, or an array of 6 numbers.
void readPair(lua_State* L, int i, KDL::Vector& first, KDL::Vector& second, std::string_view first_name,
              std::string_view second_name, std::string_view form) {
  if (isArrayOf(L, i, 6, form)) {
    double v[6];
    readArray(L, i, v, 6, form);
    first = KDL::Vector(v[0], v[1], v[2]);
    second = KDL::Vector(v[3], v[4], v[5]);
    return;
  }
  auto vec = [](lua_State* S, int j, KDL::Vector& p, std::string_view f) { readVector(S, j, p, f); };
  readMember(L, i, first_name, first, form, vec);
  readMember(L, i, second_name, second, form, vec);
}

void pushPair(lua_State* L, const KDL::Vector& first, const KDL::Vector& second, const char* first_name,
              const char* second_name) {
  lua_createtable(L, 0, 2);
  LuaCodec<KDL::Vector>::push(L, first);
  lua_setfield(L, -2, first_name);
  LuaCodec<KDL::Vector>::push(L, second);
  lua_setfield(L, -2, second_name);
}

constexpr std::string_view kVectorOfDoubleForm = "an array of numbers {1, 2.5, 3}";
constexpr std::string_view kJntArrayForm = "an array of joint values {q1, q2, ...}";
constexpr std::string_view kTaskStateForm = "a state path \"root.on.moving\"";

}  // namespace

// ---- cobra's own types (the forms are listed in lua_codec.hpp) -------------------------------

std::string_view LuaCodec<double>::form() { return "a number"; }
void LuaCodec<double>::read(lua_State* L, int i, double& out) {
  if (lua_type(L, i) != LUA_TNUMBER) refuse(L, i, "a number");
  out = static_cast<double>(lua_tonumber(L, i));
}
void LuaCodec<double>::push(lua_State* L, const double& v) { lua_pushnumber(L, v); }

std::string_view LuaCodec<int>::form() { return "an integer"; }
void LuaCodec<int>::read(lua_State* L, int i, int& out) {
  constexpr std::string_view form = "an integer";
  if (lua_type(L, i) != LUA_TNUMBER) refuse(L, i, form);
  const double d = static_cast<double>(lua_tonumber(L, i));
  if (!lua_isinteger(L, i) && std::floor(d) != d) refuse(L, i, form, "not an integer");
  if (!(d >= std::numeric_limits<int>::min() && d <= std::numeric_limits<int>::max()))
    refuse(L, i, form, "outside the int range [-2147483648, 2147483647]");
  out = static_cast<int>(d);
}
void LuaCodec<int>::push(lua_State* L, const int& v) { lua_pushinteger(L, v); }

std::string_view LuaCodec<bool>::form() { return "true or false"; }
void LuaCodec<bool>::read(lua_State* L, int i, bool& out) {
  if (lua_type(L, i) != LUA_TBOOLEAN) refuse(L, i, "true or false");
  out = lua_toboolean(L, i) != 0;
}
void LuaCodec<bool>::push(lua_State* L, const bool& v) { lua_pushboolean(L, v ? 1 : 0); }

std::string_view LuaCodec<std::string>::form() { return "a string"; }
void LuaCodec<std::string>::read(lua_State* L, int i, std::string& out) {
  if (lua_type(L, i) != LUA_TSTRING) refuse(L, i, "a string");
  std::size_t n = 0;
  const char* s = lua_tolstring(L, i, &n);
  out.assign(s, n);
}
void LuaCodec<std::string>::push(lua_State* L, const std::string& v) { lua_pushlstring(L, v.data(), v.size()); }

std::string_view LuaCodec<std::vector<double>>::form() { return kVectorOfDoubleForm; }
void LuaCodec<std::vector<double>>::read(lua_State* L, int i, std::vector<double>& out) {
  if (lua_type(L, i) != LUA_TTABLE) refuse(L, i, kVectorOfDoubleForm);
  out.resize(static_cast<std::size_t>(lua_rawlen(L, i)));  // keeps capacity: no allocation in steady state
  readArray(L, i, out.data(), out.size(), kVectorOfDoubleForm);
}
void LuaCodec<std::vector<double>>::push(lua_State* L, const std::vector<double>& v) {
  pushArray(L, v.data(), v.size());
}

std::string_view LuaCodec<KDL::Vector>::form() { return kVectorForm; }
void LuaCodec<KDL::Vector>::read(lua_State* L, int i, KDL::Vector& out) { readVector(L, i, out); }
void LuaCodec<KDL::Vector>::push(lua_State* L, const KDL::Vector& v) { pushFields(L, v.data, {"x", "y", "z"}); }

std::string_view LuaCodec<KDL::Rotation>::form() { return kRotationForm; }
void LuaCodec<KDL::Rotation>::read(lua_State* L, int i, KDL::Rotation& out) { readRotation(L, i, out); }
void LuaCodec<KDL::Rotation>::push(lua_State* L, const KDL::Rotation& r) {
  double q[4];
  r.GetQuaternion(q[0], q[1], q[2], q[3]);
  pushFields(L, q, {"x", "y", "z", "w"});
}

std::string_view LuaCodec<KDL::Frame>::form() { return kFrameForm; }
void LuaCodec<KDL::Frame>::read(lua_State* L, int i, KDL::Frame& out) {
  if (isArrayOf(L, i, 7, kFrameForm)) {
    double v[7];
    readArray(L, i, v, 7, kFrameForm);
    const double norm = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
    if (!(std::abs(norm - 1.0) <= 1e-6))
      refuse(L, i, kFrameForm, "its quaternion's norm is " + core::printValue(norm) + ", not 1");
    out = KDL::Frame(KDL::Rotation::Quaternion(v[3], v[4], v[5], v[6]), KDL::Vector(v[0], v[1], v[2]));
    return;
  }
  readMember(L, i, "p", out.p, kFrameForm, [](lua_State* S, int j, KDL::Vector& p, std::string_view f) { readVector(S, j, p, f); });
  readMember(L, i, "M", out.M, kFrameForm, [](lua_State* S, int j, KDL::Rotation& m, std::string_view f) { readRotation(S, j, m, f); });
}
void LuaCodec<KDL::Frame>::push(lua_State* L, const KDL::Frame& f) {
  lua_createtable(L, 0, 2);
  LuaCodec<KDL::Vector>::push(L, f.p);
  lua_setfield(L, -2, "p");
  LuaCodec<KDL::Rotation>::push(L, f.M);
  lua_setfield(L, -2, "M");
}

std::string_view LuaCodec<KDL::Twist>::form() { return kTwistForm; }
void LuaCodec<KDL::Twist>::read(lua_State* L, int i, KDL::Twist& out) {
  readPair(L, i, out.vel, out.rot, "vel", "rot", kTwistForm);
}
void LuaCodec<KDL::Twist>::push(lua_State* L, const KDL::Twist& t) { pushPair(L, t.vel, t.rot, "vel", "rot"); }

std::string_view LuaCodec<KDL::Wrench>::form() { return kWrenchForm; }
void LuaCodec<KDL::Wrench>::read(lua_State* L, int i, KDL::Wrench& out) {
  readPair(L, i, out.force, out.torque, "force", "torque", kWrenchForm);
}
void LuaCodec<KDL::Wrench>::push(lua_State* L, const KDL::Wrench& w) {
  pushPair(L, w.force, w.torque, "force", "torque");
}

std::string_view LuaCodec<KDL::JntArray>::form() { return kJntArrayForm; }
void LuaCodec<KDL::JntArray>::read(lua_State* L, int i, KDL::JntArray& out) {
  if (lua_type(L, i) != LUA_TTABLE) refuse(L, i, kJntArrayForm);
  const auto n = static_cast<unsigned>(lua_rawlen(L, i));
  if (out.rows() != n) out.resize(n);  // allocates only when the joint count changes
  readArray(L, i, out.data.data(), n, kJntArrayForm);
}
void LuaCodec<KDL::JntArray>::push(lua_State* L, const KDL::JntArray& q) { pushArray(L, q.data.data(), q.rows()); }

std::string_view LuaCodec<core::Event>::form() { return kEventForm; }
void LuaCodec<core::Event>::read(lua_State* L, int i, core::Event& out) {
  i = lua_absindex(L, i);
  constexpr std::size_t capacity = decltype(out.name)::capacity();
  auto text = [&](int j, std::string_view what) -> std::string_view {
    std::size_t n = 0;
    const char* s = lua_tolstring(L, j, &n);
    if (n > capacity) refuse(L, i, kEventForm, std::string(what) + " is longer than " + std::to_string(capacity) + " characters");
    return {s, n};
  };
  if (lua_type(L, i) == LUA_TSTRING) {
    out = core::Event{text(i, "the name"), {}, std::chrono::nanoseconds(0)};
    return;
  }
  if (lua_type(L, i) != LUA_TTABLE) refuse(L, i, kEventForm);
  StackGuard guard(L);
  core::Event event;
  detail::rawField(L, i, "name");
  if (lua_type(L, -1) != LUA_TSTRING) refuse(L, i, kEventForm, "field 'name' is " + describeLuaValue(L, -1));
  event.name = text(-1, "the name");
  detail::rawField(L, i, "source");
  if (lua_type(L, -1) == LUA_TSTRING) event.source = text(-1, "the source");
  else if (!lua_isnil(L, -1)) refuse(L, i, kEventForm, "field 'source' is " + describeLuaValue(L, -1));
  detail::rawField(L, i, "stamp");
  if (lua_type(L, -1) == LUA_TNUMBER) {
    const double seconds = static_cast<double>(lua_tonumber(L, -1));
    if (!(std::abs(seconds) < 9e9)) refuse(L, i, kEventForm, "field 'stamp' is outside +-9e9 s");
    event.stamp = std::chrono::nanoseconds(std::llround(seconds * 1e9));
  } else if (!lua_isnil(L, -1)) {
    refuse(L, i, kEventForm, "field 'stamp' is " + describeLuaValue(L, -1));
  }
  out = event;
}
void LuaCodec<core::Event>::push(lua_State* L, const core::Event& e) {
  lua_createtable(L, 0, 3);
  lua_pushlstring(L, e.name.view().data(), e.name.size());
  lua_setfield(L, -2, "name");
  lua_pushlstring(L, e.source.view().data(), e.source.size());
  lua_setfield(L, -2, "source");
  lua_pushnumber(L, std::chrono::duration<double>(e.stamp).count());
  lua_setfield(L, -2, "stamp");
}

std::string_view LuaCodec<core::TaskState>::form() { return kTaskStateForm; }
void LuaCodec<core::TaskState>::read(lua_State* L, int i, core::TaskState& out) {
  if (lua_type(L, i) != LUA_TSTRING) refuse(L, i, kTaskStateForm);
  std::size_t n = 0;
  const char* s = lua_tolstring(L, i, &n);
  const std::string_view path(s, n);
  constexpr std::size_t capacity = decltype(out.path)::capacity();
  if (path.empty() || n > capacity || path.find_first_of(" \t") != std::string_view::npos)
    refuse(L, i, kTaskStateForm, "a path is 1 to " + std::to_string(capacity) + " characters without blanks");
  out.path = path;
}
void LuaCodec<core::TaskState>::push(lua_State* L, const core::TaskState& s) {
  lua_pushlstring(L, s.path.view().data(), s.path.size());
}

// ---- The registry ----------------------------------------------------------------------------

namespace convert_detail {
bool onOwnersThread(const core::PropertyBase& property) {
  const core::Component* owner = property.owner();
  return owner != nullptr && owner->activity().isActivityThread();
}
void refuseWrite(const core::PortBase& port, const core::Error& e) {
  throw core::Error("port " + port.fullName() + " is a " + std::string(port.type().name) + ": cannot write it: " + e.what());
}
}  // namespace convert_detail

namespace {

/// Append-only, fixed capacity: entries never move, so a reader scans the first `count` entries
/// without a lock (the count is published after the entry is written).
struct Registry {
  static constexpr std::size_t kCapacity = 256;
  std::mutex write_mutex;
  std::array<std::optional<std::type_index>, kCapacity> ids{};
  std::array<Conversion, kCapacity> entries{};
  std::atomic<std::size_t> count{0};
};

Registry& rawRegistry() {
  static Registry r;
  return r;
}

/// The registry, with cobra's own types (core::BuiltinDataTypes) added at its first use.
void add(std::type_index id, const Conversion& conversion);

/// The registry, with cobra's own types (core::BuiltinDataTypes) added first, at its first use.
Registry& registry() {
  static const bool seeded = [] {
    core::forEachType(core::BuiltinDataTypes{}, [](auto type) {
      using T = typename decltype(type)::type;
      add(std::type_index(typeid(T)), conversionOf<T>());
    });
    return true;
  }();
  (void)seeded;
  return rawRegistry();
}

void add(std::type_index id, const Conversion& conversion) {
  Registry& r = rawRegistry();
  std::lock_guard lock(r.write_mutex);
  const std::size_t n = r.count.load(std::memory_order_relaxed);
  for (std::size_t i = 0; i < n; ++i) {
    if (*r.ids[i] == id) return;
    if (r.entries[i].type_name == conversion.type_name)
      throw core::Error("cobra: two types are registered for Lua as '" + std::string(conversion.type_name) +
                        "'; give one of them another DataTypeTraits<T>::name");
  }
  if (n == Registry::kCapacity)
    throw core::Error("cobra: the Lua conversion registry is full (" + std::to_string(Registry::kCapacity) +
                      " types); cannot add " + std::string(conversion.type_name));
  r.ids[n] = id;
  r.entries[n] = conversion;
  r.count.store(n + 1, std::memory_order_release);
}

}  // namespace

void addConversion(std::type_index id, const Conversion& conversion) {
  (void)registry();  // cobra's own types first
  add(id, conversion);
}

const Conversion* findConversion(const core::TypeInfo& type) {
  Registry& r = registry();
  const std::size_t n = r.count.load(std::memory_order_acquire);
  for (std::size_t i = 0; i < n; ++i)
    if (*r.ids[i] == type.id) return &r.entries[i];
  return nullptr;
}

const Conversion* findConversion(std::string_view type_name) {
  Registry& r = registry();
  const std::size_t n = r.count.load(std::memory_order_acquire);
  for (std::size_t i = 0; i < n; ++i)
    if (r.entries[i].type_name == type_name) return &r.entries[i];
  return nullptr;
}

std::string conversionNames() {
  Registry& r = registry();
  const std::size_t n = r.count.load(std::memory_order_acquire);
  std::string text;
  for (std::size_t i = 0; i < n; ++i) text += (text.empty() ? "" : ", ") + std::string(r.entries[i].type_name);
  return text;
}

}  // namespace cobra::script
