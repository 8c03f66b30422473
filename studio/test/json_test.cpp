// The studio's JSON (studio/src/json.cpp, on nlohmann-json): every kind of value read in order,
// strings written and read back, numbers to nine digits, errors that say where and what was
// expected, the depth bound, and the inputs a client asks for.

#include "cobra/studio/json.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cobra/test_support/test_support.hpp"

namespace cobra::studio::json {
namespace {

using cobra::test_support::messageOf;

TEST(StudioJson, ReadsEveryKindOfValueWithMembersInTheOrderWritten) {
  const Json v = parse(R"( { "b": true, "n": -1.5e3, "s": "x", "a": [1, null, false, {}], "o": { "k": [] } } )");
  ASSERT_TRUE(v.is_object());
  ASSERT_EQ(v.size(), 5U);
  EXPECT_EQ(v.begin().key(), "b");
  EXPECT_TRUE(find(v, "b")->get<bool>());
  EXPECT_EQ(find(v, "n")->get<double>(), -1500.0);
  EXPECT_EQ(stringMember(v, "s"), "x");
  EXPECT_EQ(stringMember(v, "n"), std::nullopt) << "not a string";
  const Json& a = *find(v, "a");
  ASSERT_EQ(a.size(), 4U);
  EXPECT_TRUE(a[1].is_null());
  EXPECT_TRUE(a[3].is_object());
  EXPECT_TRUE(find(*find(v, "o"), "k")->is_array());
  EXPECT_EQ(find(v, "missing"), nullptr);
  EXPECT_EQ(find(a[0], "k"), nullptr) << "not an object";
  EXPECT_EQ(describe(v), "an object");
  EXPECT_EQ(describe(a), "an array");
  EXPECT_EQ(describe(a[1]), "null");
  EXPECT_EQ(describe(*find(v, "n")), "the number -1500");
  EXPECT_EQ(describe(*find(v, "s")), "the string \"x\"");
}

TEST(StudioJson, EscapesQuotesBackslashesAndControlCharactersAndReadsThemBack) {
  EXPECT_EQ(quoted("a\"b\\c\nd\x01"), "\"a\\\"b\\\\c\\nd\\u0001\"");
  const std::string text = "quote \" backslash \\ tab \t newline \n bell \x07 é";
  EXPECT_EQ(parse(json::quoted(text)).get<std::string>(), text);
  EXPECT_EQ(parse(R"("\u00e9\ud83d\ude00\/")").get<std::string>(), "\xC3\xA9\xF0\x9F\x98\x80/");
  EXPECT_EQ(quoted("bad \xff byte"), "\"bad \xEF\xBF\xBD byte\"") << "invalid UTF-8 is replaced, never written as is";
  EXPECT_EQ(errorBody("no \"x\""), "{\"error\":\"no \\\"x\\\"\"}");
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

TEST(StudioJson, ErrorsSayWhereAndWhatWasExpected) {
  EXPECT_EQ(messageOf([] { (void)parse("{\"a\": 1,\n \"b\" 2}"); }), "JSON: line 2, column 6: expected ':' after the member name");
  EXPECT_EQ(messageOf([] { (void)parse("[1, 2"); }), "JSON: line 1, column 6: expected ',' or ']' in an array");
  EXPECT_EQ(messageOf([] { (void)parse("{\"a\": 1 \"b\"}"); }), "JSON: line 1, column 11: expected ',' or '}' in an object");
  EXPECT_EQ(messageOf([] { (void)parse("{1: 2}"); }), "JSON: line 1, column 2: expected a member name (a string)");
  EXPECT_EQ(messageOf([] { (void)parse("{\"a\": tru}"); }),
            "JSON: line 1, column 10: expected a value (an object, array, string, number, true, false or null)");
  EXPECT_EQ(messageOf([] { (void)parse(""); }), "JSON: line 1, column 1: expected a value");
  EXPECT_EQ(messageOf([] { (void)parse("\"open"); }), "JSON: line 1, column 6: expected the closing '\"' of a string");
  EXPECT_EQ(messageOf([] { (void)parse("{} x"); }), "JSON: line 1, column 4: expected the end of the document after the value");
  EXPECT_EQ(messageOf([] { (void)parse("\"\\x\""); }), "JSON: line 1, column 3: expected one of \\\" \\\\ \\/ \\b \\f \\n \\r \\t \\u");
  EXPECT_EQ(messageOf([] { (void)parse("\"a\x01\""); }), "JSON: line 1, column 3: expected no control character inside a string (escape it)");
  EXPECT_EQ(messageOf([] { (void)parse("\"\\u12\""); }), "JSON: line 1, column 6: expected 4 hexadecimal digits after \\u");
  EXPECT_EQ(messageOf([] { (void)parse("\"\\ud800\\u0041\""); }), "JSON: line 1, column 13: expected a low surrogate after a high one");
  EXPECT_EQ(messageOf([] { (void)parse("\"\xff\""); }), "JSON: line 1, column 2: expected UTF-8 text in a string");
  EXPECT_EQ(messageOf([] { (void)parse("1e999"); }).rfind("JSON: expected a number a double can hold", 0), 0U);
}

TEST(StudioJson, NestingIsBoundedAndTheErrorSaysWhere) {
  EXPECT_EQ(messageOf([] { (void)parse(std::string(100, '[')); }),
            "JSON: line 1, column 66: expected at most 64 nested arrays and objects");
  // Brackets inside strings do not count; the 65 levels the bound allows parse.
  EXPECT_EQ(messageOf([] { (void)parse("[\"[[[[\", " + std::string(64, '[') + std::string(65, ']')); }), "(no error)");
  EXPECT_EQ(messageOf([] { (void)parse("{\"a\": [[\"]\", [[1]]]]}", 2); }),
            "JSON: line 1, column 14: expected at most 2 nested arrays and objects");
  EXPECT_EQ(tryParse(std::string(100, '[')), std::nullopt);
}

TEST(StudioJson, AnInputRequestIsItsNameAndAnythingElseIsNothing) {
  EXPECT_EQ(inputRequest(R"({"type": "input", "name": "go"})", true), "go");
  EXPECT_EQ(inputRequest(R"({"name": "go", "type": "input"})", true), "go") << "in any order";
  EXPECT_EQ(inputRequest(R"({"name": "go"})", true), std::nullopt) << "a WebSocket message says its type";
  EXPECT_EQ(inputRequest(R"({"name": "go"})", false), "go");
  EXPECT_EQ(inputRequest(R"({"type": "input", "name": 3})", true), std::nullopt);
  EXPECT_EQ(inputRequest(R"({"type": "input", "name": "g\u00e9"})", true), "g\xC3\xA9");
  EXPECT_EQ(inputRequest("{\"name\":", false), std::nullopt) << "truncated";
  EXPECT_EQ(inputRequest("[\"name\", \"go\"]", false), std::nullopt);
  EXPECT_EQ(inputRequest("{\"name\": \"" + std::string(kMaxMessageBytes, 'x') + "\"}", false), std::nullopt) << "too long";
}

}  // namespace
}  // namespace cobra::studio::json
