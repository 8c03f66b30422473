// The little JSON of cobra studio (studio/src/json.cpp): escaping, numbers, members.

#include <gtest/gtest.h>

#include <cmath>

#include "cobra/studio/json.hpp"

namespace cobra::studio::json {
namespace {

TEST(StudioJson, EscapesQuotesBackslashesAndControlCharacters) {
  EXPECT_EQ(quoted("a\"b\\c\nd\x01"), "\"a\\\"b\\\\c\\nd\\u0001\"");
}

TEST(StudioJson, WritesNumbersToNineDigitsAndNonFiniteAsNull) {
  std::string out;
  appendNumber(out, 0.123456789012);
  out += ',';
  appendNumber(out, NAN);
  out += ',';
  appendNumber(out, INFINITY);
  out += ',';
  appendNumber(out, -2);
  EXPECT_EQ(out, "0.123456789,null,null,-2");
}

TEST(StudioJson, FindsAMemberOfAnyKindSkippingNestedValuesAndStrings) {
  const std::string text = R"({"model": {"a": [1, {"b": "}"}]}, "frames" : [[1,2],[3]], "n": 4, "s": "x\"y"})";
  EXPECT_EQ(member(text, "model"), R"({"a": [1, {"b": "}"}]})");
  EXPECT_EQ(member(text, "frames"), "[[1,2],[3]]");
  EXPECT_EQ(member(text, "n"), "4");
  EXPECT_EQ(member(text, "b"), "") << "only the top level's members";
  EXPECT_EQ(member("[1]", "n"), "");
  std::string s;
  EXPECT_TRUE(stringMember(text, "s", s));
  EXPECT_EQ(s, "x\"y");
  EXPECT_FALSE(stringMember(text, "n", s));
  EXPECT_FALSE(stringMember("{\"name\":", "name", s)) << "truncated";
}

}  // namespace
}  // namespace cobra::studio::json
