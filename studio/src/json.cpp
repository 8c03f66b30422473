#include "cobra/studio/json.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace cobra::studio::json {
namespace {

// Skips blanks from `i`.
std::size_t skipBlanks(std::string_view text, std::size_t i) {
  while (i < text.size() && (text[i] == ' ' || text[i] == '\n' || text[i] == '\r' || text[i] == '\t')) ++i;
  return i;
}

// The end of the string starting at `i` (a quote): the index after its closing quote; npos if unclosed.
std::size_t stringEnd(std::string_view text, std::size_t i) {
  for (++i; i < text.size(); ++i) {
    if (text[i] == '\\') ++i;
    else if (text[i] == '"') return i + 1;
  }
  return std::string_view::npos;
}

// The end of the value starting at `i`: after its closing bracket, quote or last character.
std::size_t valueEnd(std::string_view text, std::size_t i) {
  if (i >= text.size()) return std::string_view::npos;
  if (text[i] == '"') return stringEnd(text, i);
  if (text[i] == '{' || text[i] == '[') {
    int depth = 0;
    while (i < text.size()) {
      const char c = text[i];
      if (c == '"') {
        i = stringEnd(text, i);
        if (i == std::string_view::npos) return i;
        continue;
      }
      if (c == '{' || c == '[') ++depth;
      if (c == '}' || c == ']') {
        if (--depth == 0) return i + 1;
      }
      ++i;
    }
    return std::string_view::npos;
  }
  while (i < text.size() && text[i] != ',' && text[i] != '}' && text[i] != ']' && text[i] != ' ' && text[i] != '\n') ++i;
  return i;
}

}  // namespace

void appendString(std::string& out, std::string_view text) {
  out += '"';
  for (const char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char escaped[8];
          std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(c));
          out += escaped;
        } else {
          out += c;
        }
    }
  }
  out += '"';
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

std::string quoted(std::string_view text) {
  std::string out;
  appendString(out, text);
  return out;
}

std::string_view member(std::string_view text, std::string_view key) {
  std::size_t i = skipBlanks(text, 0);
  if (i >= text.size() || text[i] != '{') return {};
  ++i;
  while (true) {
    i = skipBlanks(text, i);
    if (i >= text.size() || text[i] != '"') return {};
    const std::size_t key_end = stringEnd(text, i);
    if (key_end == std::string_view::npos) return {};
    const std::string_view name = text.substr(i + 1, key_end - i - 2);
    i = skipBlanks(text, key_end);
    if (i >= text.size() || text[i] != ':') return {};
    i = skipBlanks(text, i + 1);
    const std::size_t end = valueEnd(text, i);
    if (end == std::string_view::npos) return {};
    if (name == key) return text.substr(i, end - i);
    i = skipBlanks(text, end);
    if (i >= text.size() || text[i] != ',') return {};
    ++i;
  }
}

bool stringMember(std::string_view text, std::string_view key, std::string& value) {
  const std::string_view raw = member(text, key);
  if (raw.size() < 2 || raw.front() != '"') return false;
  value.clear();
  for (std::size_t i = 1; i + 1 < raw.size(); ++i) {
    char c = raw[i];
    if (c == '\\' && i + 2 < raw.size()) {
      c = raw[++i];
      if (c == 'n') c = '\n';
      else if (c == 't') c = '\t';
      else if (c == 'r') c = '\r';
      else if (c == 'u') return false;  // no input name needs one
    }
    value += c;
  }
  return true;
}

}  // namespace cobra::studio::json
