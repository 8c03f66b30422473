// Geometry.PointList, the plan the OpenIGTLink bridge publishes: its text form both ways, its Lua
// value both ways (with the refusals), its CSV column, and the bounds of a fixed-size list.
#include "cobra/types/point_list.hpp"

#include <gtest/gtest.h>

#include <any>
#include <lua.hpp>

#include "cobra/components/reporting/csv_codec.hpp"
#include "cobra/core/error.hpp"
#include "cobra/script/convert.hpp"
#include "cobra/script/lua_state.hpp"
#include "cobra/types/register_type.hpp"

namespace cobra::types {
namespace {

using Traits = core::DataTypeTraits<PointList>;

PointList sample() {
  PointList list;
  list.add("entry", "needle path", KDL::Vector(0.1, -0.02, 0.05));
  list.add("target, deep", "needle \"path\"", KDL::Vector(0.12, 0.0, 0.11));  // a comma and quotes in names
  return list;
}

TEST(PointList, TextFormRoundTripsWithQuotedNames) {
  const std::string text = Traits::print(sample());
  EXPECT_EQ(text,
            "[{name = \"entry\", group = \"needle path\", position = [0.1, -0.02, 0.05]}, {name = \"target, deep\", "
            "group = \"needle \\\"path\\\"\", position = [0.12, 0, 0.11]}]");
  PointList parsed;
  ASSERT_TRUE(Traits::parse(text, parsed));
  EXPECT_EQ(parsed, sample());
  ASSERT_TRUE(Traits::parse(" [ ] ", parsed));
  EXPECT_EQ(parsed.count, 0U);
}

TEST(PointList, RefusesMalformedTextAndLeavesTheValue) {
  PointList value = sample();
  for (const char* bad : {"", "{}", "[{name = \"a\", group = \"g\"}]", "[{name = \"a\", group = \"g\", position = [1, 2]}]",
                          "[{name = \"a\", group = \"g\", position = [1, 2, 3], extra = 1}]",
                          "[{name = \"a\", group = \"g\", position = [1, 2, 3]},]",
                          "[{name = \"a name of more than thirty-one chars\", group = \"g\", position = [1, 2, 3]}]"}) {
    EXPECT_FALSE(Traits::parse(bad, value)) << bad;
    EXPECT_EQ(value, sample()) << bad;
  }
}

TEST(PointList, HoldsAtMost32PointsAndCutsLongNames) {
  PointList list;
  for (std::size_t i = 0; i < PointList::kCapacity; ++i) EXPECT_TRUE(list.add("p" + std::to_string(i), "g", KDL::Vector::Zero()));
  EXPECT_FALSE(list.add("one more", "g", KDL::Vector::Zero()));
  EXPECT_EQ(list.count, PointList::kCapacity);
  PointList one;
  one.add(std::string(40, 'n'), "g", KDL::Vector::Zero());
  EXPECT_EQ(one.points[0].name.size(), PointList::kNameLength);
  ASSERT_NE(list.find("p31"), nullptr);
  EXPECT_EQ(list.find("p32"), nullptr);
}

TEST(PointList, IsALuaValueAndACsvColumnOnceRegistered) {
  registerPointList();
  const script::Conversion* conversion = script::findConversion(core::typeInfo<PointList>());
  ASSERT_NE(conversion, nullptr);
  script::LuaState lua;
  lua.run("value = {{name = 'entry', group = 'plan', position = {0.1, 0.2, 0.3}}, "
          "{name = 'target', group = 'plan', position = {0, 0, 0.1}}}");
  lua_getglobal(lua.get(), "value");
  std::any read;
  conversion->read(lua.get(), -1, read);
  const auto& got = std::any_cast<const PointList&>(read);
  ASSERT_EQ(got.count, 2U);
  EXPECT_EQ(got.points[1].name, "target");
  EXPECT_EQ(got.points[0].position, KDL::Vector(0.1, 0.2, 0.3));
  conversion->push(lua.get(), read);
  lua_setglobal(lua.get(), "pushed");
  EXPECT_EQ(lua.evaluate("#pushed .. ' ' .. pushed[2].name .. ' ' .. pushed[1].group"), "2 target plan");
  for (const char* bad : {"value = {{name = 'a', group = 'g'}}", "value = {{name = 'a', group = 1, position = {0, 0, 0}}}",
                          "value = {{name = 'a', group = 'g', position = {0, 0, 0}, colour = 'red'}}"}) {
    lua.run(bad);
    lua_getglobal(lua.get(), "value");
    EXPECT_THROW(conversion->read(lua.get(), -1, read), core::Error) << bad;
    lua_settop(lua.get(), 0);
  }
  const components::CsvType* csv = components::findCsvType(core::typeInfo<PointList>());
  ASSERT_NE(csv, nullptr);
  EXPECT_EQ(csv->columns("m", 0).size(), 1U);  // its text form
}

}  // namespace
}  // namespace cobra::types
