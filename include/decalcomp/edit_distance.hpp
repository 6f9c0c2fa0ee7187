#pragma once
// How far apart two words are, for "did you mean" suggestions (JSON keys, command names).
#include <cstddef>
#include <string>

namespace decalcomp {

// Levenshtein distance: the number of single-character insertions, deletions and substitutions.
std::size_t editDistance(const std::string& a, const std::string& b);

}  // namespace decalcomp
