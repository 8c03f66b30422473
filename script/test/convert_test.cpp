// Conversions between Lua and every built-in type: round trips, both accepted input forms, the
// form produced, and refusals with their message text.

#include "cobra/script/convert.hpp"

#include <gtest/gtest.h>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <lua.hpp>

#include "cobra/core/error.hpp"
#include "cobra/core/record.hpp"
#include "cobra/script/lua_state.hpp"

namespace {
struct Gains {
  double stiffness = 0.0;
  int samples = 0;
};
struct Probe {
  double depth = 0.0;
  std::string label;
  KDL::Frame pose;
  Gains gains;
};
}  // namespace

template <>
struct cobra::core::DataTypeTraits<Gains> : cobra::core::RecordTraits<Gains> {
  static constexpr std::string_view name = "script_test.Gains";
  static constexpr auto fields = std::tuple{field("stiffness", &Gains::stiffness, "N/m"), field("samples", &Gains::samples)};
};
template <>
struct cobra::core::DataTypeTraits<Probe> : cobra::core::RecordTraits<Probe> {
  static constexpr std::string_view name = "script_test.Probe";
  static constexpr auto fields = std::tuple{field("depth", &Probe::depth, "m"), field("label", &Probe::label),
                                            field("pose", &Probe::pose), field("gains", &Probe::gains)};
};

namespace cobra::script {
namespace {

class Convert : public testing::Test {
 protected:
  template <class T>
  const Conversion& conversion() {
    const Conversion* c = findConversion(core::typeInfo<T>());
    EXPECT_NE(c, nullptr);
    return *c;
  }

  /// The C++ value of the Lua expression `expression` read as a T.
  template <class T>
  T fromLua(const std::string& expression) {
    lua.run("value = " + expression);
    lua_getglobal(lua.get(), "value");
    std::any out;
    conversion<T>().read(lua.get(), -1, out);
    lua_pop(lua.get(), 1);
    return std::any_cast<T>(out);
  }

  /// The message refusing `expression` as a T.
  template <class T>
  std::string refusal(const std::string& expression) {
    const int top = lua_gettop(lua.get());
    try {
      fromLua<T>(expression);
    } catch (const core::Error& e) {
      lua_settop(lua.get(), top);
      return e.what();
    }
    return "(accepted)";
  }

  /// Pushes `value`, stores it in the global `pushed`, and reads it back.
  template <class T>
  T roundTrip(const T& value) {
    conversion<T>().push(lua.get(), std::any(value));
    lua_pushvalue(lua.get(), -1);
    lua_setglobal(lua.get(), "pushed");
    std::any out;
    conversion<T>().read(lua.get(), -1, out);
    lua_pop(lua.get(), 1);
    return std::any_cast<T>(out);
  }

  LuaState lua;
};

TEST_F(Convert, EveryBuiltinTypeHasAConversion) {
  for (const char* name : {"double", "int", "bool", "string", "vector<double>", "KDL.Vector", "KDL.Rotation",
                           "KDL.Frame", "KDL.Twist", "KDL.Wrench", "KDL.JntArray", "Event", "TaskState"})
    EXPECT_NE(findConversion(std::string_view(name)), nullptr) << name;
  EXPECT_EQ(findConversion(std::string_view("no.Such")), nullptr);
}

TEST_F(Convert, Scalars) {
  EXPECT_EQ(roundTrip(1.25), 1.25);
  EXPECT_EQ(fromLua<double>("3"), 3.0);
  EXPECT_EQ(roundTrip(-7), -7);
  EXPECT_EQ(lua.evaluate("math.type(pushed)"), "integer");
  EXPECT_EQ(fromLua<int>("2.0"), 2);
  EXPECT_EQ(roundTrip(true), true);
  EXPECT_EQ(roundTrip(std::string("a\0b", 3)), std::string("a\0b", 3));
}

TEST_F(Convert, ScalarRefusals) {
  EXPECT_EQ(refusal<int>("1.5"), "expected an integer, got the number 1.5 (not an integer)");
  EXPECT_EQ(refusal<int>("2^40"), "expected an integer, got the number 1099511627776 (outside the int range "
                                  "[-2147483648, 2147483647])");
  EXPECT_EQ(refusal<double>("'1.5'"), "expected a number, got the string \"1.5\"");
  EXPECT_EQ(refusal<bool>("1"), "expected true or false, got the integer 1");
  EXPECT_EQ(refusal<std::string>("{}"), "expected a string, got a table");
}

TEST_F(Convert, VectorOfDoubleIsAnArray) {
  EXPECT_EQ(roundTrip(std::vector<double>{1, 2.5, -3}), (std::vector<double>{1, 2.5, -3}));
  EXPECT_EQ(lua.evaluate("#pushed .. ':' .. pushed[2]"), "3:2.5");
  EXPECT_TRUE(fromLua<std::vector<double>>("{}").empty());
  EXPECT_EQ(refusal<std::vector<double>>("{1, 'x'}"),
            "expected an array of numbers {1, 2.5, 3}, got a table (element 2 is the string \"x\")");
}

TEST_F(Convert, KdlVectorIsARecordOrAnArray) {
  EXPECT_EQ(roundTrip(KDL::Vector(1, 2, 3)), KDL::Vector(1, 2, 3));
  EXPECT_EQ(lua.evaluate("pushed.x + 10 * pushed.z"), "31.0");
  EXPECT_EQ(fromLua<KDL::Vector>("{4, 5, 6}"), KDL::Vector(4, 5, 6));
  EXPECT_EQ(fromLua<KDL::Vector>("{z = 6, y = 5, x = 4}"), KDL::Vector(4, 5, 6));
  EXPECT_EQ(refusal<KDL::Vector>("{x = 1, y = 2}"),
            "expected {x=, y=, z=} (m) or {x, y, z}, got a table (field 'z' is nil)");
  EXPECT_EQ(refusal<KDL::Vector>("{1, 2}"), "expected {x=, y=, z=} (m) or {x, y, z}, got a table (an array of 2 elements)");
}

TEST_F(Convert, KdlRotationIsAUnitQuaternion) {
  const KDL::Rotation r = KDL::Rotation::RPY(0.1, -0.2, 0.3);
  EXPECT_TRUE(KDL::Equal(roundTrip(r), r, 1e-12));
  EXPECT_EQ(lua.evaluate("pushed.w > 0.9"), "true");
  EXPECT_TRUE(KDL::Equal(fromLua<KDL::Rotation>("{0, 0, math.sin(0.25), math.cos(0.25)}"), KDL::Rotation::RotZ(0.5), 1e-12));
  EXPECT_EQ(refusal<KDL::Rotation>("{x = 0, y = 0, z = 0, w = 2}"),
            "expected a unit quaternion {x=, y=, z=, w=} or {qx, qy, qz, qw}, got a table (its norm is 2, not 1)");
}

TEST_F(Convert, KdlFrameIsPositionAndRotation) {
  const KDL::Frame f(KDL::Rotation::RotX(0.7), KDL::Vector(0.1, 0.2, 0.3));
  EXPECT_TRUE(KDL::Equal(roundTrip(f), f, 1e-12));
  EXPECT_EQ(lua.evaluate("pushed.p.y"), "0.2");
  EXPECT_TRUE(KDL::Equal(fromLua<KDL::Frame>("{p = {1, 2, 3}, M = {x = 0, y = 0, z = 0, w = 1}}"),
                         KDL::Frame(KDL::Vector(1, 2, 3)), 1e-12));
  EXPECT_TRUE(KDL::Equal(fromLua<KDL::Frame>("{1, 2, 3, 0, 0, 0, 1}"), KDL::Frame(KDL::Vector(1, 2, 3)), 1e-12));
  EXPECT_EQ(refusal<KDL::Frame>("{p = {1, 2, 3}}"),
            "expected {p = {x=, y=, z=}, M = {x=, y=, z=, w=}} or {x, y, z, qx, qy, qz, qw}, got a table "
            "(field 'M' is nil)");
}

TEST_F(Convert, TwistAndWrenchArePairsOfVectors) {
  const KDL::Twist t(KDL::Vector(1, 2, 3), KDL::Vector(4, 5, 6));
  EXPECT_EQ(roundTrip(t), t);
  EXPECT_EQ(lua.evaluate("pushed.rot.x"), "4.0");
  EXPECT_EQ(fromLua<KDL::Twist>("{1, 2, 3, 4, 5, 6}"), t);
  const KDL::Wrench w(KDL::Vector(-1, 0, 9.81), KDL::Vector(0, 0.5, 0));
  EXPECT_EQ(roundTrip(w), w);
  EXPECT_EQ(lua.evaluate("pushed.force.z"), "9.81");
  EXPECT_EQ(fromLua<KDL::Wrench>("{force = {-1, 0, 9.81}, torque = {x = 0, y = 0.5, z = 0}}"), w);
  EXPECT_EQ(refusal<KDL::Wrench>("{force = {1, 2, 3}, torque = 'none'}"),
            "expected {force = {x=, y=, z=}, torque = {x=, y=, z=}} (N, N·m) or {fx, fy, fz, tx, ty, tz}, got a "
            "table (field 'torque' is the string \"none\")");
}

TEST_F(Convert, JntArrayIsAnArray) {
  KDL::JntArray q(3);
  q(0) = 0.1;
  q(1) = -0.2;
  q(2) = 1.5;
  EXPECT_EQ(roundTrip(q), q);
  EXPECT_EQ(fromLua<KDL::JntArray>("{1, 2, 3, 4}").rows(), 4u);
}

TEST_F(Convert, EventIsARecordOrAName) {
  const core::Event e{"e_done", "Planner", std::chrono::milliseconds(1500)};
  EXPECT_EQ(roundTrip(e), e);
  EXPECT_EQ(lua.evaluate("pushed.name .. '@' .. pushed.source .. '@' .. pushed.stamp"), "e_done@Planner@1.5");
  EXPECT_EQ(fromLua<core::Event>("'e_go'"), (core::Event{"e_go", {}, {}}));
  EXPECT_EQ(refusal<core::Event>("string.rep('e', 64)").substr(0, 20), "expected an event na");
  EXPECT_NE(refusal<core::Event>("string.rep('e', 64)").find("the name is longer than 63 characters"), std::string::npos);
  EXPECT_EQ(refusal<core::Event>("{source = 'X'}"),
            "expected an event name \"e_done\" or {name=, source=, stamp=} (stamp in s), got a table (field 'name' is nil)");
}

TEST_F(Convert, TaskStateIsItsPath) {
  core::TaskState s;
  s.path = "root.on.moving";
  EXPECT_EQ(roundTrip(s), s);
  EXPECT_EQ(lua.evaluate("pushed"), "root.on.moving");
  EXPECT_EQ(refusal<core::TaskState>("'a b'"),
            "expected a state path \"root.on.moving\", got the string \"a b\" (a path is 1 to 127 characters without blanks)");
}

class ConvertRecord : public Convert {
 protected:
  ConvertRecord() {
    registerLuaType<Gains>();
    registerLuaType<Probe>();
  }
  static Probe sample() {
    Probe p;
    p.depth = 0.05;
    p.label = "liver";
    p.pose = KDL::Frame(KDL::Rotation::RotZ(0.5), KDL::Vector(0.1, 0.2, 0.3));
    p.gains = {250.0, 7};
    return p;
  }
};

TEST_F(ConvertRecord, IsATableOfItsFieldsEachInItsOwnForm) {
  ASSERT_NE(findConversion(std::string_view("script_test.Probe")), nullptr);
  EXPECT_EQ(findConversion(core::typeInfo<Probe>())->lua_form, "a table {depth=, label=, pose=, gains=} (script_test.Probe)");
  const Probe back = roundTrip(sample());
  EXPECT_EQ(back.depth, 0.05);
  EXPECT_EQ(back.label, "liver");
  EXPECT_TRUE(KDL::Equal(back.pose, sample().pose, 1e-12));
  EXPECT_EQ(back.gains.stiffness, 250.0);
  EXPECT_EQ(back.gains.samples, 7);
  EXPECT_EQ(lua.evaluate("pushed.label .. ' ' .. pushed.pose.p.z .. ' ' .. math.type(pushed.gains.samples)"),
            "liver 0.3 integer");
  const Probe written = fromLua<Probe>(
      "{depth = 1, label = 'x', pose = {1, 2, 3, 0, 0, 0, 1}, gains = {samples = 2, stiffness = 0.5}}");
  EXPECT_EQ(written.depth, 1.0);
  EXPECT_EQ(written.pose.p, KDL::Vector(1, 2, 3));
  EXPECT_EQ(written.gains.samples, 2);
  EXPECT_NE(conversionNames().find("KDL.JntArray, Event, TaskState, script_test.Gains, script_test.Probe"), std::string::npos)
      << conversionNames();
}

TEST_F(ConvertRecord, RefusalsNameTheField) {
  EXPECT_EQ(refusal<Gains>("3"), "expected a table {stiffness=, samples=} (script_test.Gains), got the integer 3");
  EXPECT_EQ(refusal<Gains>("{stiffness = 'x', samples = 1}"),
            "field 'stiffness': expected a number, got the string \"x\"");
  EXPECT_EQ(refusal<Gains>("{stiffness = 1}"), "field 'samples': expected an integer, got nil");
  EXPECT_EQ(refusal<Gains>("{stiffness = 1, samples = 1, stifness = 2}"),
            "expected a table {stiffness=, samples=} (script_test.Gains), got a table (script_test.Gains has no field "
            "'stifness')");
  EXPECT_EQ(refusal<Gains>("{stiffness = 1, samples = 1, 5}"),
            "expected a table {stiffness=, samples=} (script_test.Gains), got a table (script_test.Gains has no field "
            "the integer 1)");
  EXPECT_EQ(refusal<Probe>("{depth = 1, label = 'x', pose = {1, 2, 3, 0, 0, 0, 1}, gains = {stiffness = 1, samples = 1.5}}"),
            "field 'gains.samples': expected an integer, got the number 1.5 (not an integer)");
  EXPECT_EQ(refusal<Probe>("{depth = 1, label = 'x', pose = {p = {1, 2, 3}}, gains = {stiffness = 1, samples = 1}}"),
            "field 'pose': expected {p = {x=, y=, z=}, M = {x=, y=, z=, w=}} or {x, y, z, qx, qy, qz, qw}, got a table "
            "(field 'M' is nil)");
}

TEST_F(ConvertRecord, RegisteringTwiceKeepsOneEntryAndANameClashIsRefused) {
  const Conversion* first = findConversion(core::typeInfo<Probe>());
  registerLuaType<Probe>();
  EXPECT_EQ(findConversion(core::typeInfo<Probe>()), first);
  Conversion clash = *first;
  try {
    addConversion(std::type_index(typeid(long)), clash);
    ADD_FAILURE() << "a second type named script_test.Probe was accepted";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("two types are registered for Lua as 'script_test.Probe'"), std::string::npos);
  }
}

TEST_F(Convert, PushingInAnExhaustedPoolIsAnErrorNotACrash) {
  LuaState small({64 * 1024, "component 'Small'", "raise its lua_pool_size property"});
  small.run("hog = {} for i = 1, 1e6 do local ok = pcall(function() hog[#hog + 1] = {i} end) if not ok then break end end");
  const Conversion& c = conversion<std::vector<double>>();
  std::string message;
  try {
    for (int i = 0; i < 100; ++i) {
      c.push(small.get(), std::any(std::vector<double>(1000, 1.0)));
      lua_setglobal(small.get(), ("big" + std::to_string(i)).c_str());
    }
  } catch (const core::Error& e) {
    message = e.what();
  }
  EXPECT_EQ(message, "Lua memory pool of component 'Small' exhausted (64 KiB); raise its lua_pool_size property");
}

TEST_F(Convert, DescribesLuaValues) {
  lua.run("value = 'a long string that goes on and on and on and on'");
  lua_getglobal(lua.get(), "value");
  EXPECT_EQ(describeLuaValue(lua.get(), -1), "the string \"a long string that goes on and on and on...\"");
  lua_pop(lua.get(), 1);
}

}  // namespace
}  // namespace cobra::script
