#include "glint/io/mesh/obj_checks.h"

#include <optional>
#include <string>

#include "glint/io/mesh/common.h"

namespace glint::mesh_io {
namespace {

// An OBJ index: [+-]digits, at most 18 of them (so it fits in 64 bits).
// parse_integer's result, faster (a large file has millions).
std::optional<int64_t> parse_index(std::string_view s) {
  size_t i = 0;
  const bool negative = !s.empty() && s[0] == '-';
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) i = 1;
  if (i == s.size() || s.size() - i > 18) return std::nullopt;
  int64_t value = 0;
  for (; i < s.size(); ++i) {
    const unsigned digit = static_cast<unsigned>(s[i]) - '0';
    if (digit > 9) return std::nullopt;
    value = value * 10 + digit;
  }
  return negative ? -value : value;
}

}  // namespace

bool is_decimal_number(std::string_view s) {
  size_t i = 0, digits = 0;
  auto is_digit = [&](size_t k) { return k < s.size() && s[k] >= '0' && s[k] <= '9'; };
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  for (; is_digit(i); ++i) ++digits;
  if (i < s.size() && s[i] == '.')
    for (++i; is_digit(i); ++i) ++digits;
  if (digits == 0) return false;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    if (!is_digit(i)) return false;
    while (is_digit(i)) ++i;
  }
  return i == s.size();
}

int find_obj_statement(std::string_view text, std::string_view keyword, size_t ordinal) {
  LineCursor lines(text);
  std::string_view line;
  size_t seen = 0;
  while (lines.next(line)) {
    const std::string_view t = skip_blanks(line);
    if (t.size() > keyword.size() && t.substr(0, keyword.size()) == keyword && is_blank(t[keyword.size()])) {
      if (seen++ == ordinal) return lines.number();
    }
  }
  return 0;
}

std::vector<BadVertexText> scan_obj_nonfinite_text(std::string_view text) {
  std::vector<BadVertexText> bad;
  if (!contains_word_ci(text, "nan") && !contains_word_ci(text, "inf")) return bad;
  LineCursor lines(text);
  std::string_view line;
  uint32_t vertex = 0;
  while (lines.next(line)) {
    const std::string_view t = skip_blanks(line);
    if (t.size() < 2 || t[0] != 'v' || !is_blank(t[1])) continue;
    const size_t offset = static_cast<size_t>(t.data() - line.data()) + 1;
    for (const Token& tok : tokens_of(t.substr(1), 3)) {
      std::string_view s = tok.text;
      if (!s.empty() && (s[0] == '+' || s[0] == '-')) s.remove_prefix(1);
      const std::string l = lower(s.substr(0, 3));
      if (l == "nan" || l == "inf")
        bad.push_back({vertex, lines.number(), static_cast<int>(offset) + tok.column, std::string(tok.text)});
    }
    ++vertex;
  }
  return bad;
}

TextProblem find_obj_bad_statement(std::string_view text) {
  LineCursor lines(text);
  std::string_view line;
  int64_t counts[3] = {0, 0, 0};  // v, vt, vn so far
  static constexpr const char* kIndexNames[3] = {"vertex", "texture coordinate", "normal"};
  static constexpr const char* kPlural[3] = {"vertices", "texture coordinates", "normals"};
  auto key_is = [](std::string_view t, std::string_view key) {
    return t.size() > key.size() && t.substr(0, key.size()) == key && is_blank(t[key.size()]);
  };
  // The next token of `t` from `pos` (blanks and \v \f separate), or empty.
  auto next_token = [](std::string_view t, size_t& pos) {
    auto blank = [](char c) { return is_blank(c) || c == '\r' || c == '\v' || c == '\f'; };
    while (pos < t.size() && blank(t[pos])) ++pos;
    const size_t start = pos;
    while (pos < t.size() && !blank(t[pos])) ++pos;
    return t.substr(start, pos - start);
  };
  while (lines.next(line)) {
    const std::string_view t = skip_blanks(line);
    if (t.size() < 2 || (t[0] != 'v' && t[0] != 'f' && t[0] != 'l' && t[0] != 'p')) continue;
    const int offset = static_cast<int>(t.data() - line.data()) + 1;  // column of t[0]
    const int kind = key_is(t, "v") ? 0 : key_is(t, "vt") ? 1 : key_is(t, "vn") ? 2 : -1;
    if (kind >= 0) {
      const size_t needed = kind == 1 ? 1 : 3;
      size_t pos = kind == 0 ? 1 : 2;
      for (size_t k = 0; k < needed; ++k) {
        const std::string_view tok = next_token(t, pos);
        const int column = offset + static_cast<int>(pos - tok.size());
        const char* what = kind == 0 ? "vertex" : kind == 1 ? "texture coordinate" : "normal";
        if (tok.empty())
          return {lines.number(), offset + static_cast<int>(pos),
                  std::string(what) + " with " + plural(k, "number", "numbers") + " (" +
                      (kind == 1 ? "u [v] needed)" : "x y z needed)")};
        if (!is_decimal_number(tok) && !parse_number(tok))
          return {lines.number(), column,
                  std::string(what) + (kind == 1 ? " '" : " coordinate '") + std::string(tok) + "' is not a number"};
      }
      ++counts[kind];
      continue;
    }
    if (!key_is(t, "f") && !key_is(t, "l") && !key_is(t, "p")) continue;
    size_t pos = 1;
    for (std::string_view tok = next_token(t, pos); !tok.empty(); tok = next_token(t, pos)) {
      const int column = offset + static_cast<int>(pos - tok.size());
      // v, v/vt, v//vn, v/vt/vn: empty parts are absent (the vertex is not).
      std::string_view part = tok;
      for (int k = 0; k < 3; ++k) {
        const size_t slash = part.find('/');
        const std::string_view index_text = part.substr(0, slash);
        if (k == 0 || !index_text.empty()) {
          const auto i = parse_index(index_text);
          if (!i) {
            const std::string_view digits = index_text.substr(index_text.starts_with('-') ? 1 : 0);
            const bool too_long = !digits.empty() && digits.find_first_not_of("0123456789") == std::string_view::npos;
            return {lines.number(), column,
                    std::string(kIndexNames[k]) + " index '" + std::string(index_text) + "'" +
                        (too_long ? " out of range" : " is not a whole number")};
          }
          if (*i == 0)
            return {lines.number(), column,
                    std::string(kIndexNames[k]) + " index of 0 (OBJ counts from 1, or back from -1)"};
          const int64_t resolved = *i > 0 ? *i - 1 : counts[k] + *i;
          if (resolved < 0 || resolved >= counts[k])
            return {lines.number(), column,
                    std::string(kIndexNames[k]) + " index " + std::string(index_text) + " out of range (" +
                        (counts[k] == 1 ? "1 " + std::string(kIndexNames[k])
                                        : std::to_string(counts[k]) + " " + kPlural[k]) +
                        (*i < 0 ? " before it)" : ")")};
        }
        if (slash == std::string_view::npos) break;
        part = part.substr(slash + 1);
        if (k == 2) break;
      }
    }
  }
  return {};
}

std::vector<size_t> scan_obj_face_sizes(std::string_view text) {
  std::vector<size_t> sizes;
  LineCursor lines(text);
  std::string_view line;
  while (lines.next(line)) {
    const std::string_view t = skip_blanks(line);
    if (t.size() < 2 || t[0] != 'f' || !is_blank(t[1])) continue;
    const size_t n = tokens_of(t.substr(1)).size();
    if (n >= 3) sizes.push_back(n);
  }
  return sizes;
}

}  // namespace glint::mesh_io
