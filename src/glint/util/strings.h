// Small string helpers shared by every folder (the loader's messages, the
// command line, pass names). Depends on nothing else of glint.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace glint {

// The closest of `candidates` to `word` if it is a plausible typo, else "".
std::string closest_match(std::string_view word, const std::vector<std::string_view>& candidates);

}  // namespace glint
