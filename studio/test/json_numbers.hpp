#pragma once
// For the studio's tests: the numbers of a JSON list the bridge wrote, without a JSON library.

#include <string>
#include <vector>

namespace cobra::studio {

// The numbers of the list after `"key":` (nested lists flattened), from `from`.
inline std::vector<double> numbersAfter(const std::string& text, const std::string& key, std::size_t from = 0) {
  std::vector<double> out;
  auto at = text.find("\"" + key + "\":[", from);
  if (at == std::string::npos) return out;
  at += key.size() + 3;
  for (int depth = 0; at < text.size();) {
    if (text[at] == '[' || text[at] == ']' || text[at] == ',') {
      depth += text[at] == '[' ? 1 : (text[at] == ']' ? -1 : 0);
      ++at;
      if (depth == 0) break;
      continue;
    }
    std::size_t used = 0;
    out.push_back(std::stod(text.substr(at, 32), &used));
    at += used;
  }
  return out;
}

}  // namespace cobra::studio
