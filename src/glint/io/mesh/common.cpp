#include "glint/io/mesh/common.h"

#include <cctype>
#include <cstdio>

namespace glint::mesh_io {

[[noreturn]] void fail(const std::string& file, const std::string& message, int line, int column) {
  throw Error(SourceLocation{file, line, column}, message);
}

std::string plural(size_t n, const char* singular, const char* plural_form) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural_form);
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string with_line(const std::string& file, int line) { return line > 0 ? file + ":" + std::to_string(line) : file; }

// Lists up to three names, then "and N more".
std::string name_list(const std::vector<std::string>& names) {
  std::string out;
  for (size_t i = 0; i < names.size() && i < 3; ++i) out += (i ? ", '" : "'") + names[i] + "'";
  if (names.size() > 3) out += " and " + std::to_string(names.size() - 3) + " more";
  return out;
}

// A count as a whole number, also beyond 64 bits ("4000000000", "1e+300").
std::string format_count(double n) {
  char buf[32];
  std::snprintf(buf, sizeof buf, n < 1e15 ? "%.0f" : "%.3g", n);
  return buf;
}

uint64_t read_binary_uint(const unsigned char* p, size_t size, bool big_endian) {
  uint64_t v = 0;
  for (size_t i = 0; i < size; ++i) v |= uint64_t(p[big_endian ? i : size - 1 - i]) << (8 * (size - 1 - i));
  return v;
}

}  // namespace glint::mesh_io
