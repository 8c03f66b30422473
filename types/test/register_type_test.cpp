// registerType<T>(): one call reaches every capability registry (core, Lua, CSV); cobra's own
// types have every capability (the image a port type only); a registered record travels through
// Lua and into CSV columns.

#include "cobra/types/register_type.hpp"

#include <gtest/gtest.h>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <lua.hpp>

#include "cobra/components/motion/path_type.hpp"
#include "cobra/core/record.hpp"
#include "cobra/script/lua_state.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/types/gray_image.hpp"
#include "cobra/types/point_list.hpp"

namespace {
struct Needle {
  double depth = 0.0;   // m
  double force = 0.0;   // N
  KDL::Vector tip;
  bool inserted = false;
};
}  // namespace

template <>
struct cobra::core::DataTypeTraits<Needle> : cobra::core::RecordTraits<Needle> {
  static constexpr std::string_view name = "types_test.Needle";
  static constexpr std::string_view cpp = "Needle";
  static constexpr auto fields = std::tuple{field("depth", &Needle::depth, "m", "insertion depth"),
                                            field("force", &Needle::force, "N", "axial force"),
                                            field("tip", &Needle::tip, "m"), field("inserted", &Needle::inserted)};
};

namespace cobra::types {
namespace {

TEST(RegisterType, ReachesEveryRegistry) {
  EXPECT_EQ(script::findConversion(std::string_view("types_test.Needle")), nullptr) << "not registered yet";
  registerType<Needle>();
  const core::TypeInfo* info = core::TypeRegistry::find("types_test.Needle");
  ASSERT_NE(info, nullptr);
  EXPECT_EQ(info->cpp, "Needle");
  ASSERT_EQ(info->fields.size(), 4u);
  EXPECT_EQ(info->fields[1].unit, "N");
  EXPECT_TRUE(hasEveryCapability(*info));
  EXPECT_EQ(script::findConversion(*info), script::findConversion(std::string_view("types_test.Needle")));
  const components::CsvType* csv = components::findCsvType(*info);
  ASSERT_NE(csv, nullptr);
  std::vector<std::string> columns;
  for (const auto& c : csv->columns("m", 0)) columns.push_back(c.suffix + " [" + c.unit + "]");
  EXPECT_EQ(columns, (std::vector<std::string>{".depth [m]", ".force [N]", ".tip.x [m]", ".tip.y [m]", ".tip.z [m]",
                                               ".inserted []"}));
  registerType<Needle>();  // idempotent
  EXPECT_EQ(components::findCsvType(*info), csv);
}

TEST(RegisterType, EveryBuiltinTypeHasEveryCapability) {
  registerBuiltins();
  std::size_t count = 0;
  core::forEachType(core::BuiltinDataTypes{}, [&](auto type) {
    const core::TypeInfo& info = core::typeInfo<typename decltype(type)::type>();
    EXPECT_TRUE(hasEveryCapability(info)) << info.name;
    EXPECT_FALSE(info.cpp.empty()) << info.name;
    ++count;
  });
  EXPECT_EQ(count, 13u);
}

TEST(RegisterType, TheBuiltinsIncludeTheMotionPlannersPathWithALuaForm) {
  registerBuiltins();
  const core::TypeInfo* path = core::TypeRegistry::find("TGL.MultiAxisPath");
  ASSERT_NE(path, nullptr);
  EXPECT_TRUE(hasEveryCapability(*path));
  const script::Conversion* conversion = script::findConversion(*path);
  script::LuaState lua;
  lua.run("value = {{0, 0.1}, {0.2, 0.3, 0.4}}");
  lua_getglobal(lua.get(), "value");
  std::any read;
  conversion->read(lua.get(), -1, read);
  const auto& got = std::any_cast<const trajectory::MultiAxisPath&>(read);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got.waypoint(1), (std::vector<double>{0.2, 0.3, 0.4}));
  conversion->push(lua.get(), read);
  lua_setglobal(lua.get(), "pushed");
  EXPECT_EQ(lua.evaluate("#pushed .. ' ' .. pushed[2][3]"), "2 0.4");
  lua.run("value = {{0, 'x'}}");
  lua_getglobal(lua.get(), "value");
  try {
    conversion->read(lua.get(), -1, read);
    ADD_FAILURE() << "a string in a path was accepted";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("(waypoint 1, value 2 is not a number)"), std::string::npos) << e.what();
  }
  lua_settop(lua.get(), 0);
  ASSERT_EQ(components::findCsvType(*path)->columns("m", 0).size(), 1u);  // its text form
}

TEST(RegisterType, TheBuiltinsIncludeThePointListWithEveryCapabilityAndTheImageAsAPortTypeOnly) {
  registerBuiltins();
  // Nothing else in this program registers either: registerBuiltins() does.
  const core::TypeInfo* points = core::TypeRegistry::find("Geometry.PointList");
  ASSERT_NE(points, nullptr);
  EXPECT_TRUE(hasEveryCapability(*points));
  EXPECT_EQ(points->unit, "m");
  const script::Conversion* conversion = script::findConversion(*points);
  EXPECT_EQ(conversion->lua_form.rfind("an array of at most 32 points", 0), 0u) << conversion->lua_form;
  EXPECT_EQ(components::findCsvType(*points)->columns("plan", 0).size(), 1u);  // its text form
  registerPointList();  // what the cobra_bridges package calls: harmless beside registerBuiltins()
  EXPECT_EQ(script::findConversion(*points), conversion);

  // The image is a port type: its name and kind, no Lua value, no CSV column (gray_image.hpp).
  const core::TypeInfo* image = core::TypeRegistry::find("Imaging.GrayImage");
  ASSERT_NE(image, nullptr);
  EXPECT_EQ(image->kind, core::DataKind::Pure);
  EXPECT_EQ(image->cpp, "cobra::types::GrayImage");
  EXPECT_EQ(script::findConversion(*image), nullptr);
  EXPECT_EQ(components::findCsvType(*image), nullptr);
}

TEST(RegisterType, ARegisteredRecordIsALuaValueOnAPort) {
  registerType<Needle>();
  core::OutputPort<Needle> out("needle", "", "m");
  core::InputPort<Needle> in("needle", "", "m");
  out.connectTo(in, core::ConnPolicy::data());
  const script::Conversion* conversion = script::findConversion(core::typeInfo<Needle>());
  ASSERT_NE(conversion, nullptr);
  script::LuaState lua;
  auto access = conversion->access(out);
  lua.run("value = {depth = 0.02, force = 1.5, tip = {x = 0, y = 0, z = -0.02}, inserted = true}");
  lua_getglobal(lua.get(), "value");
  access->write(lua.get(), -1);
  lua_pop(lua.get(), 1);
  Needle got;
  ASSERT_EQ(in.read(got), core::FlowStatus::NewData);
  EXPECT_EQ(got.force, 1.5);
  EXPECT_EQ(got.tip.z(), -0.02);
  EXPECT_TRUE(got.inserted);
  // Real-time: writing a record from Lua reads it into the access's buffer, allocating nothing.
  lua_getglobal(lua.get(), "value");
  EXPECT_EQ(test_support::allocationsDuring([&] {
              for (int i = 0; i < 100; ++i) access->write(lua.get(), -1);
            }),
            0);
  lua_pop(lua.get(), 1);
  lua.run("value = {depth = 0.02, force = 'strong', tip = {0, 0, 0}, inserted = true}");
  lua_getglobal(lua.get(), "value");
  try {
    access->write(lua.get(), -1);
    ADD_FAILURE() << "a string force was accepted";
  } catch (const core::Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "port needle is a types_test.Needle: cannot write it: field 'force': expected a number, got the string "
              "\"strong\"");
  }
}

}  // namespace
}  // namespace cobra::types
