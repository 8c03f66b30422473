#pragma once
/// @file
/// cobra studio's JSON (studio/PROTOCOL.md), on nlohmann-json: reading a client's messages, the
/// editor's requests and recordings with bounded depth and errors that say where and what was
/// expected; writing strings and numbers into the messages the bridge streams.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace cobra::studio::json {

/// A JSON document; objects keep their members in the order written (an editor's project, a
/// recording's model).
using Json = nlohmann::ordered_json;

/// At most this many nested arrays and objects: a request nests a few levels; deeper is an attack.
inline constexpr int kMaxDepth = 64;
/// A client's message over the WebSocket or an HTTP body: at most this many bytes.
inline constexpr std::size_t kMaxMessageBytes = 1 << 20;

/// Parses `text` (one JSON value, nothing after it but blanks), nesting at most `max_depth`
/// arrays and objects.
/// @throws std::runtime_error "JSON: line L, column C: expected WHAT".
Json parse(std::string_view text, int max_depth = kMaxDepth);
/// As `parse`, but nothing when `text` is not JSON (or too deep): for a client's messages,
/// which are ignored when malformed.
std::optional<Json> tryParse(std::string_view text, int max_depth = kMaxDepth);

/// Member `key` of `value`, or nullptr (also when `value` is not an object).
const Json* find(const Json& value, std::string_view key);
/// The string member `key` of `value`, or nothing when absent or not a string.
std::optional<std::string> stringMember(const Json& value, std::string_view key);

/// The input a client asks for (studio/PROTOCOL.md): the name of `{"type": "input", "name":
/// NAME}` (a WebSocket message, `with_type`) or of `{"name": NAME}` (the body of POST
/// /api/input); nothing for any other or malformed text, or one over kMaxMessageBytes.
std::optional<std::string> inputRequest(std::string_view text, bool with_type);

/// "an object", "the string \"x\"", "the number 3", "null": what `value` is, for messages.
std::string describe(const Json& value);

/// Appends `text` as a JSON string (quoted, escaped; invalid UTF-8 replaced by U+FFFD).
void appendString(std::string& out, std::string_view text);
/// `text` as a JSON string.
std::string quoted(std::string_view text);
/// Appends a number with up to 9 significant digits (m: 1 nm at 1 m); NaN and infinities as
/// null. The bridge's frames carry thousands of numbers: 9 digits keep them short where
/// nlohmann's own writer gives the 17 a double round-trips with.
void appendNumber(std::string& out, double value);
/// `{"error": TEXT}`: the body of every error answer.
std::string errorBody(std::string_view text);

}  // namespace cobra::studio::json
