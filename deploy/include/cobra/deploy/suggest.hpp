#pragma once
/// @file
/// "Did you mean" suggestions for misspelt names, shared by the deployer and the console.

#include <string>
#include <string_view>
#include <vector>

namespace cobra::deploy {

/// Levenshtein distance between `a` and `b`, case-sensitive.
std::size_t editDistance(std::string_view a, std::string_view b);

/// The names of `known` closest to `wanted` (at most 3, only those within a distance that makes
/// a typo plausible: a third of the longer name, at least 2), best first.
std::vector<std::string> closestNames(std::string_view wanted, const std::vector<std::string>& known);

/// "; did you mean 'Gain'? known types: A, B, C" (or "; known types: (none)"), ready to append
/// to an error message. `what` names the list, e.g. "types".
std::string suggestionText(std::string_view wanted, const std::vector<std::string>& known, std::string_view what);

}  // namespace cobra::deploy
