#include "cobra/deploy/suggest.hpp"

#include <algorithm>
#include <numeric>

namespace cobra::deploy {

std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), std::size_t{0});
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::vector<std::string> closestNames(std::string_view wanted, const std::vector<std::string>& known) {
  std::vector<std::pair<std::size_t, std::string>> scored;
  for (const std::string& name : known) {
    const std::size_t limit = std::max<std::size_t>(2, std::max(wanted.size(), name.size()) / 3);
    const std::size_t distance = editDistance(wanted, name);
    if (distance <= limit) scored.emplace_back(distance, name);
  }
  std::stable_sort(scored.begin(), scored.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<std::string> out;
  for (std::size_t i = 0; i < scored.size() && i < 3; ++i) out.push_back(scored[i].second);
  return out;
}

std::string suggestionText(std::string_view wanted, const std::vector<std::string>& known, std::string_view what) {
  std::string text;
  const std::vector<std::string> close = closestNames(wanted, known);
  if (!close.empty()) {
    text += "; did you mean ";
    for (std::size_t i = 0; i < close.size(); ++i)
      text += (i == 0 ? "'" : i + 1 == close.size() ? " or '" : ", '") + close[i] + "'";
    text += "?";
  } else {
    text += ";";
  }
  text += " known " + std::string(what) + ": ";
  if (known.empty()) return text + "(none)";
  // Long lists are cut: the suggestion above is what matters, the list shows what exists.
  constexpr std::size_t kListed = 40;
  for (std::size_t i = 0; i < known.size() && i < kListed; ++i) text += (i == 0 ? "" : ", ") + known[i];
  if (known.size() > kListed) text += ", ... (" + std::to_string(known.size() - kListed) + " more)";
  return text;
}

}  // namespace cobra::deploy
