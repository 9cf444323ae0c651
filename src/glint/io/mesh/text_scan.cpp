#include "glint/io/mesh/text_scan.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <system_error>

namespace glint::mesh_io {

std::vector<Token> tokens_of(std::string_view line, size_t max_tokens) {
  std::vector<Token> out;
  size_t i = 0;
  while (i < line.size() && out.size() < max_tokens) {
    while (i < line.size() && (is_blank(line[i]) || line[i] == '\r' || line[i] == '\v' || line[i] == '\f')) ++i;
    if (i >= line.size()) break;
    const size_t start = i;
    while (i < line.size() && !(is_blank(line[i]) || line[i] == '\r' || line[i] == '\v' || line[i] == '\f')) ++i;
    out.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
  }
  return out;
}

std::optional<double> parse_number(std::string_view s) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double value = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (end != s.data() + s.size()) return std::nullopt;
  if (ec == std::errc::result_out_of_range) {
    // Underflow reads as zero, overflow as infinity.
    const std::string digits(s);
    const double approx = std::strtod(digits.c_str(), nullptr);
    return std::isinf(approx) ? approx : 0.0;
  }
  if (ec != std::errc()) return std::nullopt;
  return value;
}

std::optional<int64_t> parse_integer(std::string_view s) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  int64_t value = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return value;
}

bool contains_word_ci(std::string_view text, std::string_view word) {
  const char first_lower = word[0];
  const char first_upper = static_cast<char>(std::toupper(static_cast<unsigned char>(first_lower)));
  for (char first : {first_lower, first_upper}) {
    size_t pos = 0;
    while ((pos = text.find(first, pos)) != std::string_view::npos) {
      if (pos + word.size() <= text.size()) {
        bool match = true;
        for (size_t k = 1; k < word.size() && match; ++k)
          match = std::tolower(static_cast<unsigned char>(text[pos + k])) == word[k];
        if (match) return true;
      }
      ++pos;
    }
  }
  return false;
}

}  // namespace glint::mesh_io
