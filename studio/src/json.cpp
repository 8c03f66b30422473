#include "cobra/studio/json.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace cobra::studio::json {
namespace {

// Thrown by the parser's callback at the first array or object nested too deep.
struct TooDeep {};

// "line L, column C" of the character at `index` (the end of `text` when past it).
std::string where(std::string_view text, std::size_t index) {
  int line = 1, column = 1;
  for (std::size_t k = 0; k < index && k < text.size(); ++k) {
    if (text[k] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// Where the first array or object deeper than `max_depth` opens. Only called once the parser
// met it, so the text before it is JSON: brackets inside strings are the only ones to skip.
std::size_t firstTooDeep(std::string_view text, int max_depth) {
  int depth = -1;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return i;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return text.size();
}

bool has(std::string_view text, std::string_view part) { return text.find(part) != std::string_view::npos; }

// What was expected, in cobra's words, from nlohmann's "syntax error while parsing CONTEXT -
// DETAIL" (its parse_error.101 text).
std::string expected(std::string_view message) {
  constexpr std::string_view kSyntax = "syntax error while parsing ";
  const std::size_t at = message.find(kSyntax);
  if (at == std::string_view::npos) {
    const std::size_t colon = message.find(": ");
    return "JSON (" + std::string(colon == std::string_view::npos ? message : message.substr(colon + 2)) + ")";
  }
  const std::string_view rest = message.substr(at + kSyntax.size());
  const std::size_t dash = rest.find(" - ");
  const std::string_view context = rest.substr(0, dash);
  const std::string_view detail = dash == std::string_view::npos ? std::string_view() : rest.substr(dash + 3);
  if (context == "object separator") return "':' after the member name";
  if (context == "object key") return "a member name (a string)";
  if (context == "object") return "',' or '}' in an object";
  if (context == "array") return "',' or ']' in an array";
  if (has(detail, "; expected end of input")) return "the end of the document after the value";
  if (has(detail, "missing closing quote")) return "the closing '\"' of a string";
  if (has(detail, "forbidden character after backslash")) return "one of \\\" \\\\ \\/ \\b \\f \\n \\r \\t \\u";
  if (has(detail, "control character")) return "no control character inside a string (escape it)";
  if (has(detail, "must be followed by 4 hex digits")) return "4 hexadecimal digits after \\u";
  if (has(detail, "surrogate U+D800..U+DBFF")) return "a low surrogate after a high one";
  if (has(detail, "surrogate U+DC00..U+DFFF")) return "a high surrogate before a low one";
  if (has(detail, "UTF-8")) return "UTF-8 text in a string";
  if (has(detail, "unexpected end of input")) return "a value";
  return "a value (an object, array, string, number, true, false or null)";
}

}  // namespace

Json parse(std::string_view text, int max_depth) {
  const Json::parser_callback_t limit = [max_depth](int depth, Json::parse_event_t event, Json&) {
    if ((event == Json::parse_event_t::object_start || event == Json::parse_event_t::array_start) && depth > max_depth)
      throw TooDeep{};
    return true;
  };
  try {
    return Json::parse(text.begin(), text.end(), limit);
  } catch (const TooDeep&) {
    throw std::runtime_error("JSON: " + where(text, firstTooDeep(text, max_depth)) + ": expected at most " +
                             std::to_string(max_depth) + " nested arrays and objects");
  } catch (const Json::parse_error& e) {
    throw std::runtime_error("JSON: " + where(text, e.byte == 0 ? 0 : e.byte - 1) + ": expected " + expected(e.what()));
  } catch (const Json::exception& e) {  // a number no double holds (out_of_range.406)
    throw std::runtime_error(std::string("JSON: expected a number a double can hold (") + e.what() + ")");
  }
}

std::optional<Json> tryParse(std::string_view text, int max_depth) {
  try {
    return parse(text, max_depth);
  } catch (const std::runtime_error&) {
    return std::nullopt;
  }
}

const Json* find(const Json& value, std::string_view key) {
  if (!value.is_object()) return nullptr;
  const auto found = value.find(key);
  return found == value.end() ? nullptr : &*found;
}

std::optional<std::string> stringMember(const Json& value, std::string_view key) {
  const Json* member = find(value, key);
  if (member == nullptr || !member->is_string()) return std::nullopt;
  return member->get<std::string>();
}

std::optional<std::string> inputRequest(std::string_view text, bool with_type) {
  if (text.size() > kMaxMessageBytes) return std::nullopt;
  const std::optional<Json> message = tryParse(text);
  if (!message) return std::nullopt;
  if (with_type && stringMember(*message, "type") != "input") return std::nullopt;
  return stringMember(*message, "name");
}

std::string describe(const Json& value) {
  switch (value.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::boolean: return value.get<bool>() ? "true" : "false";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float: {
      std::string n;
      appendNumber(n, value.get<double>());
      return "the number " + n;
    }
    case Json::value_t::string: return "the string " + json::quoted(value.get_ref<const std::string&>());
    case Json::value_t::array: return "an array";
    case Json::value_t::object: return "an object";
    default: return "a value";
  }
}

void appendString(std::string& out, std::string_view text) {
  out += Json(text).dump(-1, ' ', false, Json::error_handler_t::replace);
}

std::string quoted(std::string_view text) {
  std::string out;
  appendString(out, text);
  return out;
}

void appendNumber(std::string& out, double value) {
  if (!std::isfinite(value)) {
    out += "null";
    return;
  }
  char text[32];
  // As printf's %.9g, several times faster (a recording writes thousands of numbers per frame).
  const auto end = std::to_chars(text, text + sizeof text, value, std::chars_format::general, 9).ptr;
  out.append(text, static_cast<std::size_t>(end - text));
}

std::string errorBody(std::string_view text) { return "{\"error\":" + json::quoted(text) + "}"; }

}  // namespace cobra::studio::json
