#pragma once
/// @file
/// The little JSON cobra studio needs (studio/PROTOCOL.md): writing messages and reading the
/// two things it reads (a string member of a client's message, a member's text in a recording).

#include <string>
#include <string_view>

namespace cobra::studio::json {

/// Appends `text` as a JSON string (quoted, escaped).
void appendString(std::string& out, std::string_view text);
/// Appends a number with up to 9 significant digits (m: 1 nm at 1 m); NaN and infinities as null.
void appendNumber(std::string& out, double value);
/// `text` as a JSON string.
std::string quoted(std::string_view text);

/// The text of member `key` of the top-level object `text` (a value of any kind, as written);
/// empty when `text` is not an object or has no such member.
std::string_view member(std::string_view text, std::string_view key);
/// The string member `key` of the top-level object `text`, unescaped; false when absent or not a string.
bool stringMember(std::string_view text, std::string_view key, std::string& value);

}  // namespace cobra::studio::json
