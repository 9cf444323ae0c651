#include "options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "glint/util/strings.h"

namespace glint::cli {

void print_error(const std::string& what) {
  std::string line;
  for (char c : what) {
    if (c == '\n') line += "\\n";
    else if (c == '\r') line += "\\r";
    else line += c;
  }
  std::fprintf(stderr, "error: %s\n", line.c_str());
}

CLI::Validator whole_number_in(long long lo, long long hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        long long value = 0;
        const char* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, value);
        if (text.empty() || ec == std::errc::invalid_argument || ptr != end)
          return "expected a whole number, got \"" + text + "\"";
        if (ec == std::errc::result_out_of_range || value < lo || value > hi)
          return "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + " (got " + text + ")";
        return {};
      },
      "INT in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

CLI::Validator number_in(double lo, double hi) {
  auto text_of = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  return CLI::Validator(
      [lo, hi, text_of](std::string& text) -> std::string {
        double value = 0;
        const char* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, value);
        if (text.empty() || ec == std::errc::invalid_argument || ptr != end || !std::isfinite(value))
          return "expected a number, got \"" + text + "\"";
        if (ec == std::errc::result_out_of_range || value < lo || value > hi)
          return "must be between " + text_of(lo) + " and " + text_of(hi) + " (got " + text + ")";
        return {};
      },
      "NUMBER in [" + text_of(lo) + ", " + text_of(hi) + "]");
}

CLI::Validator one_of(std::vector<std::string_view> names, std::string what) {
  std::string list;
  for (std::string_view n : names) {
    if (!list.empty()) list += '|';
    list += n;
  }
  return CLI::Validator(
      [names, what](std::string& text) -> std::string {
        if (std::find(names.begin(), names.end(), text) != names.end()) return {};
        std::string msg = "unknown " + what + " \"" + text + "\"";
        const std::string hint = glint::closest_match(text, names);
        if (!hint.empty()) return msg + " (did you mean \"" + hint + "\"?)";
        msg += " (expected one of";
        for (size_t i = 0; i < names.size(); ++i) msg += (i ? ", \"" : " \"") + std::string(names[i]) + "\"";
        return msg + ")";
      },
      list);
}

}  // namespace glint::cli
