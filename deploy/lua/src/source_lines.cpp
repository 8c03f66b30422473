#include "source_lines.hpp"

#include <cctype>
#include <fstream>

namespace cobra::deploy::detail {

SourceLines::SourceLines(const std::string& path) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) lines_.push_back(line);
}

namespace {
bool isIdentifierChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

/// True when `line` assigns to `name` ("name = {", "local name = {").
bool definesList(const std::string& line, const std::string& name) {
  for (std::size_t at = line.find(name); at != std::string::npos; at = line.find(name, at + 1)) {
    const bool starts = at == 0 || !isIdentifierChar(line[at - 1]);
    const std::size_t end = at + name.size();
    if (!starts || (end < line.size() && isIdentifierChar(line[end]))) continue;
    std::size_t i = line.find_first_not_of(" \t", end);
    if (i == std::string::npos || line[i] != '=' || (i + 1 < line.size() && line[i + 1] == '=')) continue;
    return true;
  }
  return false;
}
}  // namespace

int SourceLines::listStart(int call_line) const {
  if (call_line < 1 || call_line > static_cast<int>(lines_.size())) return 0;
  const std::string& call = lines_[call_line - 1];
  const std::size_t open = call.find('(');
  if (open == std::string::npos) return call_line;
  std::size_t i = call.find_first_not_of(" \t", open + 1);
  if (i == std::string::npos || call[i] == '{') return call_line;
  std::size_t end = i;
  while (end < call.size() && isIdentifierChar(call[end])) ++end;
  const std::string name = call.substr(i, end - i);
  if (name.empty()) return call_line;
  for (int line = call_line; line >= 1; --line)
    if (definesList(lines_[line - 1], name)) return line;
  for (int line = call_line + 1; line <= static_cast<int>(lines_.size()); ++line)
    if (definesList(lines_[line - 1], name)) return line;
  return 0;
}

int SourceLines::find(int from, const std::vector<std::string>& needles) const {
  for (int line = std::max(from, 1); line <= static_cast<int>(lines_.size()); ++line) {
    bool all = true;
    for (const std::string& needle : needles) all = all && lines_[line - 1].find(needle) != std::string::npos;
    if (all) return line;
  }
  return 0;
}

}  // namespace cobra::deploy::detail
