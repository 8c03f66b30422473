// Every Lua <-> C++ value conversion of cobra, in one table keyed by type name.

#include "cobra/script/convert.hpp"

#include <array>
#include <cmath>
#include <limits>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/core/activity.hpp"
#include "cobra/core/component.hpp"
#include "lua_guard.hpp"
#include "port_access.hpp"

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

namespace {

/// Restores the stack top on scope exit (lua_settop raises nothing).
class StackGuard {
 public:
  explicit StackGuard(lua_State* L) : L_(L), top_(lua_gettop(L)) {}
  ~StackGuard() { lua_settop(L_, top_); }
  StackGuard(const StackGuard&) = delete;
  StackGuard& operator=(const StackGuard&) = delete;

 private:
  lua_State* L_;
  int top_;
};

[[noreturn]] void refuse(lua_State* L, int index, std::string_view form, std::string_view detail = {}) {
  throw core::Error("expected " + std::string(form) + ", got " + describeLuaValue(L, index) +
                    (detail.empty() ? "" : " (" + std::string(detail) + ")"));
}

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

template <class T>
struct Converter;

template <>
struct Converter<double> {
  static void read(lua_State* L, int i, double& out) {
    if (lua_type(L, i) != LUA_TNUMBER) refuse(L, i, "a number");
    out = static_cast<double>(lua_tonumber(L, i));
  }
  static void push(lua_State* L, const double& v) { lua_pushnumber(L, v); }
};

template <>
struct Converter<int> {
  static void read(lua_State* L, int i, int& out) {
    constexpr std::string_view form = "an integer";
    if (lua_type(L, i) != LUA_TNUMBER) refuse(L, i, form);
    const double d = static_cast<double>(lua_tonumber(L, i));
    if (!lua_isinteger(L, i) && std::floor(d) != d) refuse(L, i, form, "not an integer");
    if (!(d >= std::numeric_limits<int>::min() && d <= std::numeric_limits<int>::max()))
      refuse(L, i, form, "outside the int range [-2147483648, 2147483647]");
    out = static_cast<int>(d);
  }
  static void push(lua_State* L, const int& v) { lua_pushinteger(L, v); }
};

template <>
struct Converter<bool> {
  static void read(lua_State* L, int i, bool& out) {
    if (lua_type(L, i) != LUA_TBOOLEAN) refuse(L, i, "true or false");
    out = lua_toboolean(L, i) != 0;
  }
  static void push(lua_State* L, const bool& v) { lua_pushboolean(L, v ? 1 : 0); }
};

template <>
struct Converter<std::string> {
  static void read(lua_State* L, int i, std::string& out) {
    if (lua_type(L, i) != LUA_TSTRING) refuse(L, i, "a string");
    std::size_t n = 0;
    const char* s = lua_tolstring(L, i, &n);
    out.assign(s, n);
  }
  static void push(lua_State* L, const std::string& v) { lua_pushlstring(L, v.data(), v.size()); }
};

template <>
struct Converter<std::vector<double>> {
  static void read(lua_State* L, int i, std::vector<double>& out) {
    constexpr std::string_view form = "an array of numbers {1, 2.5, 3}";
    if (lua_type(L, i) != LUA_TTABLE) refuse(L, i, form);
    out.resize(static_cast<std::size_t>(lua_rawlen(L, i)));  // keeps capacity: no allocation in steady state
    readArray(L, i, out.data(), out.size(), form);
  }
  static void push(lua_State* L, const std::vector<double>& v) { pushArray(L, v.data(), v.size()); }
};

template <>
struct Converter<KDL::Vector> {
  static void read(lua_State* L, int i, KDL::Vector& out) { readVector(L, i, out); }
  static void push(lua_State* L, const KDL::Vector& v) { pushFields(L, v.data, {"x", "y", "z"}); }
};

template <>
struct Converter<KDL::Rotation> {
  static void read(lua_State* L, int i, KDL::Rotation& out) { readRotation(L, i, out); }
  static void push(lua_State* L, const KDL::Rotation& r) {
    double q[4];
    r.GetQuaternion(q[0], q[1], q[2], q[3]);
    pushFields(L, q, {"x", "y", "z", "w"});
  }
};

template <>
struct Converter<KDL::Frame> {
  static void read(lua_State* L, int i, KDL::Frame& out) {
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
  static void push(lua_State* L, const KDL::Frame& f) {
    lua_createtable(L, 0, 2);
    Converter<KDL::Vector>::push(L, f.p);
    lua_setfield(L, -2, "p");
    Converter<KDL::Rotation>::push(L, f.M);
    lua_setfield(L, -2, "M");
  }
};

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
  Converter<KDL::Vector>::push(L, first);
  lua_setfield(L, -2, first_name);
  Converter<KDL::Vector>::push(L, second);
  lua_setfield(L, -2, second_name);
}

template <>
struct Converter<KDL::Twist> {
  static void read(lua_State* L, int i, KDL::Twist& out) { readPair(L, i, out.vel, out.rot, "vel", "rot", kTwistForm); }
  static void push(lua_State* L, const KDL::Twist& t) { pushPair(L, t.vel, t.rot, "vel", "rot"); }
};

template <>
struct Converter<KDL::Wrench> {
  static void read(lua_State* L, int i, KDL::Wrench& out) {
    readPair(L, i, out.force, out.torque, "force", "torque", kWrenchForm);
  }
  static void push(lua_State* L, const KDL::Wrench& w) { pushPair(L, w.force, w.torque, "force", "torque"); }
};

template <>
struct Converter<KDL::JntArray> {
  static void read(lua_State* L, int i, KDL::JntArray& out) {
    constexpr std::string_view form = "an array of joint values {q1, q2, ...}";
    if (lua_type(L, i) != LUA_TTABLE) refuse(L, i, form);
    const auto n = static_cast<unsigned>(lua_rawlen(L, i));
    if (out.rows() != n) out.resize(n);  // allocates only when the joint count changes
    readArray(L, i, out.data.data(), n, form);
  }
  static void push(lua_State* L, const KDL::JntArray& q) { pushArray(L, q.data.data(), q.rows()); }
};

template <>
struct Converter<core::Event> {
  static void read(lua_State* L, int i, core::Event& out) {
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
  static void push(lua_State* L, const core::Event& e) {
    lua_createtable(L, 0, 3);
    lua_pushlstring(L, e.name.view().data(), e.name.size());
    lua_setfield(L, -2, "name");
    lua_pushlstring(L, e.source.view().data(), e.source.size());
    lua_setfield(L, -2, "source");
    lua_pushnumber(L, std::chrono::duration<double>(e.stamp).count());
    lua_setfield(L, -2, "stamp");
  }
};

// ---- Generic parts, instantiated once per type -------------------------------------------

template <class T>
int pushThunk(lua_State* L) {
  Converter<T>::push(L, *static_cast<const T*>(lua_touserdata(L, 1)));
  return 1;
}

/// Pushes `value`; numbers and booleans directly (no allocation), the rest in protected mode.
template <class T>
void pushValue(lua_State* L, const T& value) {
  if constexpr (std::is_arithmetic_v<T>) Converter<T>::push(L, value);
  else detail::protectedCall(L, &pushThunk<T>, &value, 1);
}

template <class T>
void readAny(lua_State* L, int index, std::any& out) {
  index = lua_absindex(L, index);  // the converters push while reading
  T value{};
  Converter<T>::read(L, index, value);
  out = std::move(value);
}

template <class T>
void pushAny(lua_State* L, const std::any& value) {
  pushValue(L, std::any_cast<const T&>(value));
}

template <class T>
core::Property<T>& typed(core::PropertyBase& property) {
  auto* p = dynamic_cast<core::Property<T>*>(&property);
  if (p == nullptr) throw core::Error(property.where() + " is not a " + std::string(core::DataTypeTraits<T>::name));
  return *p;
}

template <class T>
std::any getProperty(const core::PropertyBase& property) {
  const core::Property<T>& p = typed<T>(const_cast<core::PropertyBase&>(property));
  // On the owner's activity thread (a hook reading its own property) changes are applied on
  // this very thread between steps: read without the lock, which could block real-time code.
  const core::Component* owner = property.owner();
  if (owner != nullptr && owner->activity().isActivityThread()) return p.get();
  return p.value();
}

template <class T>
void setProperty(core::PropertyBase& property, const std::any& value) {
  typed<T>(property).set(std::any_cast<const T&>(value));
}

/// Port access with preallocated buffers: read/write copy into them, never allocate once they
/// have the data's size.
template <class T>
class TypedPortAccess final : public PortAccess {
 public:
  explicit TypedPortAccess(core::PortBase& port)
      : PortAccess(port),
        input_(dynamic_cast<core::InputPort<T>*>(&port)),
        output_(dynamic_cast<core::OutputPort<T>*>(&port)) {}

  int read(lua_State* L) override {
    core::InputPort<T>* input = input_;
    if (input == nullptr) {
      // An output port (read from a console): through a private data connection made at the
      // first read, so that read sees only what is written after it.
      if (!reader_) {
        auto reader = std::make_unique<core::InputPort<T>>("lua_reader_" + port().name(),
                                                           "Lua reader of " + port().fullName(), port().unit());
        output_->connectTo(*reader, core::ConnPolicy::data());
        reader_ = std::move(reader);
      }
      input = reader_.get();
    }
    const core::FlowStatus status = input->read(read_buffer_);
    pushStatus(L, status);
    if (status == core::FlowStatus::NoData) lua_pushnil(L);
    else pushValue(L, read_buffer_);
    return 2;
  }

  int write(lua_State* L, int index) override {
    if (output_ == nullptr) throwNotOutput();
    try {
      Converter<T>::read(L, index, write_buffer_);
    } catch (const core::Error& e) {
      throw core::Error("port " + port().fullName() + " is a " + std::string(port().type().name) +
                        ": cannot write it: " + e.what());
    }
    output_->write(write_buffer_);
    return 0;
  }

 private:
  core::InputPort<T>* input_;
  core::OutputPort<T>* output_;
  std::unique_ptr<core::InputPort<T>> reader_;  // reads an output port; declared after output_
  T read_buffer_{};
  T write_buffer_{};
};

template <class T>
std::unique_ptr<PortAccess> makeAccess(core::PortBase& port) {
  return std::make_unique<TypedPortAccess<T>>(port);
}

template <class T>
std::unique_ptr<core::PortBase> makePort(core::PortDirection direction, std::string name, std::string doc,
                                         std::string unit) {
  if (direction == core::PortDirection::Input)
    return std::make_unique<core::InputPort<T>>(std::move(name), std::move(doc), std::move(unit));
  return std::make_unique<core::OutputPort<T>>(std::move(name), std::move(doc), std::move(unit));
}

template <class T>
std::unique_ptr<core::PropertyBase> makeProperty(std::string name, const std::any& initial, std::string unit,
                                                 std::string doc) {
  return std::make_unique<core::Property<T>>(std::move(name), std::any_cast<const T&>(initial), std::move(unit),
                                             std::move(doc));
}

template <class T>
Conversion entry(std::string_view form) {
  return {core::DataTypeTraits<T>::name, form, &readAny<T>, &pushAny<T>, &getProperty<T>, &setProperty<T>,
          &makeAccess<T>, &makePort<T>, &makeProperty<T>};
}

const std::array<Conversion, 12>& table() {
  static const std::array<Conversion, 12> conversions{
      entry<double>("a number"),
      entry<int>("an integer"),
      entry<bool>("true or false"),
      entry<std::string>("a string"),
      entry<std::vector<double>>("an array of numbers {1, 2.5, 3}"),
      entry<KDL::Vector>(kVectorForm),
      entry<KDL::Rotation>(kRotationForm),
      entry<KDL::Frame>(kFrameForm),
      entry<KDL::Twist>(kTwistForm),
      entry<KDL::Wrench>(kWrenchForm),
      entry<KDL::JntArray>("an array of joint values {q1, q2, ...}"),
      entry<core::Event>(kEventForm),
  };
  return conversions;
}

}  // namespace

const Conversion* findConversion(std::string_view type_name) {
  for (const Conversion& c : table())
    if (c.type_name == type_name) return &c;
  return nullptr;
}

const Conversion* findConversion(const core::TypeInfo& type) { return findConversion(type.name); }

std::string conversionNames() {
  std::string names;
  for (const Conversion& c : table()) names += (names.empty() ? "" : ", ") + std::string(c.type_name);
  return names;
}

}  // namespace cobra::script
