#include "cobra/core/record.hpp"

#include "cobra/text/trim.hpp"

namespace cobra::core::record_detail {
namespace {

using text::trim;

bool isIdentifier(std::string_view name) {
  if (name.empty() || (name.front() >= '0' && name.front() <= '9')) return false;
  for (char c : name)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_')) return false;
  return true;
}

/// Adds "name = value" to `items`; false when it is not of that form.
bool addItem(std::string_view item, std::vector<std::pair<std::string_view, std::string_view>>& items) {
  const auto equals = item.find('=');
  if (equals == std::string_view::npos) return false;
  const std::string_view name = trim(item.substr(0, equals));
  const std::string_view value = trim(item.substr(equals + 1));
  if (!isIdentifier(name) || value.empty()) return false;
  items.emplace_back(name, value);
  return true;
}

}  // namespace

bool split(std::string_view text, std::vector<std::pair<std::string_view, std::string_view>>& items) {
  text = trim(text);
  if (text.size() < 2 || text.front() != '{' || text.back() != '}') return false;
  text = trim(text.substr(1, text.size() - 2));
  items.clear();
  if (text.empty()) return true;
  int depth = 0;
  bool in_string = false;
  std::size_t start = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;  // the escaped character
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') in_string = true;
    else if (c == '[' || c == '{') ++depth;
    else if (c == ']' || c == '}') {
      if (--depth < 0) return false;
    } else if (c == ',' && depth == 0) {
      if (!addItem(text.substr(start, i - start), items)) return false;
      start = i + 1;
    }
  }
  return !in_string && depth == 0 && addItem(text.substr(start), items);
}

std::string quote(std::string_view text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

bool unquote(std::string_view text, std::string& out) {
  text = trim(text);
  if (text.size() < 2 || text.front() != '"' || text.back() != '"') return false;
  std::string value;
  for (std::size_t i = 1; i + 1 < text.size(); ++i) {
    char c = text[i];
    if (c == '\\') {
      if (i + 2 >= text.size()) return false;  // a lone escape before the closing quote
      c = text[++i];
    } else if (c == '"') {
      return false;  // an unescaped quote inside
    }
    value += c;
  }
  out = std::move(value);
  return true;
}

}  // namespace cobra::core::record_detail
