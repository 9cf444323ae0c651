// Text scanners the mesh readers share: lines as tinyobjloader splits them,
// tokens with their columns, numbers as strtod reads them. The libraries
// parse; these find what they misread, and where (file:line:col).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <streambuf>
#include <string>
#include <string_view>
#include <vector>

namespace glint::mesh_io {

// Lines as tinyobjloader splits them: "\n", "\r\n" or a lone "\r" ends one.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : text_(text) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const size_t start = pos_;
    // memchr (vectorized) for the '\n', then for a '\r' before it.
    const char* begin = text_.data() + start;
    const char* nl = static_cast<const char*>(std::memchr(begin, '\n', text_.size() - start));
    const char* end = nl ? nl : text_.data() + text_.size();
    if (const void* cr = std::memchr(begin, '\r', static_cast<size_t>(end - begin))) end = static_cast<const char*>(cr);
    pos_ = static_cast<size_t>(end - text_.data());
    line = text_.substr(start, pos_ - start);
    if (pos_ < text_.size()) {
      if (text_[pos_] == '\r' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '\n') ++pos_;
      ++pos_;
    }
    ++number_;
    return true;
  }
  int number() const { return number_; }  // of the line `next` returned, 1-based

 private:
  std::string_view text_;
  size_t pos_ = 0;
  int number_ = 0;
};

inline bool is_blank(char c) { return c == ' ' || c == '\t'; }

inline std::string_view skip_blanks(std::string_view s) {
  size_t i = 0;
  while (i < s.size() && is_blank(s[i])) ++i;
  return s.substr(i);
}

// Whitespace-separated tokens of a line, with their 1-based columns.
struct Token {
  std::string_view text;
  int column;
};
std::vector<Token> tokens_of(std::string_view line, size_t max_tokens = SIZE_MAX);

// A number as strtod reads it (leading '+' allowed); nullopt if it is not one.
// Out-of-range values come back as +-inf, so callers see them as non-finite.
std::optional<double> parse_number(std::string_view s);

std::optional<int64_t> parse_integer(std::string_view s);

// True when `text` holds `word` in any letter case (word given in lower case).
bool contains_word_ci(std::string_view text, std::string_view word);

// An istream over bytes in memory, without copying them.
class MemoryStreambuf : public std::streambuf {
 public:
  MemoryStreambuf(const char* data, size_t size) {
    char* p = const_cast<char*>(data);
    setg(p, p, p + size);
  }
};

// Where a text file goes wrong: 1-based line and column (line 0: nowhere).
struct TextProblem {
  int line = 0, column = 0;
  std::string message;
};

}  // namespace glint::mesh_io
