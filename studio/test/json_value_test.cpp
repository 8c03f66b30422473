// The editor's JSON reader (json_value.hpp): every kind of value, escapes, and errors that say
// where and what was expected.

#include "cobra/studio/json_value.hpp"

#include <gtest/gtest.h>

#include <string>

#include "cobra/studio/json.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::studio::json {
namespace {

using cobra::test_support::messageOf;

TEST(JsonValue, ReadsEveryKindOfValueInOrder) {
  const Value v = parse(R"( { "b": true, "n": -1.5e3, "s": "x", "a": [1, null, false, {}], "o": { "k": [] } } )");
  ASSERT_TRUE(v.isObject());
  ASSERT_EQ(v.members().size(), 5u);
  EXPECT_EQ(v.members()[0].first, "b");  // members in the order written
  EXPECT_TRUE(v.find("b")->boolean());
  EXPECT_EQ(v.find("n")->number(), -1500.0);
  EXPECT_EQ(v.find("s")->string(), "x");
  const auto& a = v.find("a")->items();
  ASSERT_EQ(a.size(), 4u);
  EXPECT_TRUE(a[1].isNull());
  EXPECT_TRUE(a[2].isBool());
  EXPECT_TRUE(a[3].isObject());
  EXPECT_TRUE(v.find("o")->find("k")->isArray());
  EXPECT_EQ(v.find("missing"), nullptr);
  EXPECT_EQ(a[0].find("k"), nullptr);  // not an object
}

TEST(JsonValue, UnescapesStringsWithTheWriterAsPeer) {
  const std::string text = "quote \" backslash \\ tab \t newline \n bell \x07 é";
  EXPECT_EQ(parse(json::quoted(text)).string(), text);  // what json.hpp writes reads back
  EXPECT_EQ(parse(R"("\u00e9\ud83d\ude00\/")").string(), "\xC3\xA9\xF0\x9F\x98\x80/");
}

TEST(JsonValue, ErrorsSayWhereAndWhatWasExpected) {
  EXPECT_EQ(messageOf([] { (void)parse("{\"a\": 1,\n \"b\" 2}"); }), "JSON: line 2, column 6: expected ':' after the member name");
  EXPECT_EQ(messageOf([] { (void)parse("[1, 2"); }), "JSON: line 1, column 6: expected ',' or ']' in an array");
  EXPECT_EQ(messageOf([] { (void)parse("{\"a\": tru}"); }),
            "JSON: line 1, column 7: expected a value (an object, array, string, number, true, false or null)");
  EXPECT_EQ(messageOf([] { (void)parse("\"open"); }), "JSON: line 1, column 6: expected the closing '\"' of a string");
  EXPECT_EQ(messageOf([] { (void)parse("{} x"); }), "JSON: line 1, column 4: expected the end of the document after the value");
  EXPECT_EQ(messageOf([] { (void)parse("\"\\x\""); }), "JSON: line 1, column 3: expected one of \\\" \\\\ \\/ \\b \\f \\n \\r \\t \\u");
  EXPECT_EQ(messageOf([] { (void)parse(std::string(100, '[')); }),
            "JSON: line 1, column 66: expected at most 64 nested arrays and objects");
}

}  // namespace
}  // namespace cobra::studio::json
