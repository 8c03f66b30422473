#pragma once
/// @file
/// White space around a word of a text format (a value's text form, a record's field list, a line
/// of a deployment set).

#include <string_view>

namespace cobra::text {

/// `text` without its leading and trailing spaces, tabs, carriage returns and newlines; empty
/// when it holds nothing else. A view into `text`.
inline std::string_view trim(std::string_view text) {
  constexpr std::string_view kSpace = " \t\r\n";
  const auto first = text.find_first_not_of(kSpace);
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(kSpace) - first + 1);
}

}  // namespace cobra::text
