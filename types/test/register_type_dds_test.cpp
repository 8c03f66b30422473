// registerType<T>() in code built with the dds headers (this test links cobra::dds) registers T
// for DDS too; the same call compiled without them (register_without_dds.cpp, as cobra::types and
// the `cobra` tool are) registers core, Lua and CSV only, and the two forms coexist in one
// program: were they one symbol, the linker would keep one of them for both translation units.
// No participant is made: no DDS domain is used.

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <typeindex>
#include <vector>

#include "cobra/core/type_facets.hpp"
#include "cobra/dds/register_type.hpp"
#include "cobra/types/register_type.hpp"
#include "probe_record.hpp"

#ifndef COBRA_TYPES_HAVE_DDS
#error "register_type_dds_test.cpp is compiled with the dds headers (it links cobra::dds)"
#endif

namespace cobra::types {
namespace {

bool carriedByDds(const std::string& name) {
  const std::vector<std::string> carried = dds::ddsTypes();
  return std::find(carried.begin(), carried.end(), name) != carried.end();
}

TEST(RegisterTypeWithDds, WithoutTheDdsHeadersNoDdsSideWithThemOneCallRegistersIt) {
  const std::type_index probe(typeid(types_test::Probe));
  const types_test::Registration without_dds = types_test::probeRegistrationWithoutDds();
  const types_test::Registration with_dds = &registerType<types_test::Probe>;
  ASSERT_NE(without_dds, with_dds) << "the forms with and without DDS are one definition (ODR)";
  without_dds();
  const core::TypeInfo* info = core::TypeRegistry::find("types_test.Probe");
  ASSERT_NE(info, nullptr);
  EXPECT_TRUE(hasEveryCapability(*info)) << "core, Lua and CSV without the dds headers";
  EXPECT_FALSE(carriedByDds("types_test.Probe")) << "the form built without dds registered the DDS side";
  EXPECT_EQ(core::TypeFacets::get(probe, dds::detail::facet), nullptr);

  with_dds();
  EXPECT_TRUE(carriedByDds("types_test.Probe")) << "registerType<T>() with the dds headers left DDS out";
  EXPECT_NE(core::TypeFacets::get(probe, dds::detail::facet), nullptr)
      << "the binding is not published for the tool's transport (a package of its own)";
  EXPECT_NE(dds::registeredIdl("types_test.Probe").find("double depth"), std::string::npos);
}

}  // namespace
}  // namespace cobra::types
