// TypeFacets (type_facets.hpp): per-type capabilities shared by every module of a process.
#include "cobra/core/type_facets.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "cobra/core/error.hpp"

namespace {

struct A {};
struct B {};
template <int N>
struct Many {};

const int facet_one = 1;
const int facet_two = 2;

TEST(TypeFacets, SetThenGetByTypeAndCapability) {
  EXPECT_EQ(cobra::core::TypeFacets::get(typeid(A), "dds"), nullptr);
  EXPECT_TRUE(cobra::core::TypeFacets::set(typeid(A), "dds", &facet_one));
  EXPECT_EQ(cobra::core::TypeFacets::get(typeid(A), "dds"), &facet_one);
  // Another capability of the same type, the same capability of another type: separate.
  EXPECT_EQ(cobra::core::TypeFacets::get(typeid(A), "ddsx"), nullptr);
  EXPECT_EQ(cobra::core::TypeFacets::get(typeid(A), "dd"), nullptr);
  EXPECT_EQ(cobra::core::TypeFacets::get(typeid(B), "dds"), nullptr);
  EXPECT_TRUE(cobra::core::TypeFacets::set(typeid(A), "lua", &facet_two));
  EXPECT_EQ(cobra::core::TypeFacets::get(typeid(A), "lua"), &facet_two);
  EXPECT_EQ(cobra::core::TypeFacets::get(typeid(A), "dds"), &facet_one);
}

TEST(TypeFacets, SecondSetKeepsTheFirst) {
  EXPECT_TRUE(cobra::core::TypeFacets::set(typeid(B), "csv", &facet_one));
  const auto size = cobra::core::TypeFacets::size();
  EXPECT_FALSE(cobra::core::TypeFacets::set(typeid(B), "csv", &facet_two));
  EXPECT_EQ(cobra::core::TypeFacets::get(typeid(B), "csv"), &facet_one);
  EXPECT_EQ(cobra::core::TypeFacets::size(), size);
}

TEST(TypeFacets, RefusesNullFacetAndBadCapabilityNames) {
  EXPECT_THROW(cobra::core::TypeFacets::set(typeid(B), "x", nullptr), cobra::core::Error);
  EXPECT_THROW(cobra::core::TypeFacets::set(typeid(B), "", &facet_one), cobra::core::Error);
  const std::string long_name(cobra::core::TypeFacets::max_capability + 1, 'c');
  EXPECT_THROW(cobra::core::TypeFacets::set(typeid(B), long_name, &facet_one), cobra::core::Error);
  const std::string longest(cobra::core::TypeFacets::max_capability, 'c');
  EXPECT_TRUE(cobra::core::TypeFacets::set(typeid(B), longest, &facet_one));
  EXPECT_EQ(cobra::core::TypeFacets::get(typeid(B), longest), &facet_one);
  EXPECT_EQ(cobra::core::TypeFacets::get(typeid(B), long_name), nullptr);
}

// Readers run while a writer publishes: every facet a reader sees is complete (tsan-checked:
// this file starts threads, so it is labelled concurrency; here a plain consistency check).
template <int... I>
void publishAll(std::integer_sequence<int, I...>, std::vector<int>& values) {
  (cobra::core::TypeFacets::set(typeid(Many<I>), "many", &values[I]), ...);
}
template <int... I>
bool seenConsistent(std::integer_sequence<int, I...>, const std::vector<int>& values) {
  bool ok = true;
  ((ok = ok && [&] {
     const void* f = cobra::core::TypeFacets::get(typeid(Many<I>), "many");
     return f == nullptr || f == &values[I];
   }()),
   ...);
  return ok;
}

TEST(TypeFacets, ReadersSeeCompleteFacetsWhileAWriterPublishes) {
  constexpr int n = 64;
  std::vector<int> values(n);
  std::atomic<bool> done{false};
  std::atomic<bool> consistent{true};
  std::thread reader([&] {
    while (!done.load())
      if (!seenConsistent(std::make_integer_sequence<int, n>{}, values)) consistent.store(false);
  });
  publishAll(std::make_integer_sequence<int, n>{}, values);
  done.store(true);
  reader.join();
  EXPECT_TRUE(consistent.load());
  EXPECT_EQ(cobra::core::TypeFacets::get(typeid(Many<n - 1>), "many"), &values[n - 1]);
}

}  // namespace
