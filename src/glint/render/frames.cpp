#include "glint/render/frames.h"

#include <charconv>

#include "glint/error.h"

namespace glint {

namespace {

std::optional<int> whole_number(std::string_view s) {
  int value = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) return std::nullopt;
  return value;
}

}  // namespace

std::vector<int> parse_frame_range(std::string_view text, int frame_count) {
  const std::string quoted = "--frames \"" + std::string(text) + "\"";
  const size_t dash = text.find('-', 1);
  const auto first = whole_number(text.substr(0, dash));
  const auto last = dash == std::string_view::npos ? first : whole_number(text.substr(dash + 1));
  if (!first || !last) throw Error(quoted + ": expected a frame N or a range A-B");
  if (*first > *last)
    throw Error(quoted + ": the range is empty (" + std::to_string(*first) + " > " + std::to_string(*last) + ")");
  if (*first < 0 || *last >= frame_count)
    throw Error(quoted + ": the scene has frames 0-" + std::to_string(frame_count - 1) +
                (frame_count == 1 ? " (it is not animated)" : ""));
  std::vector<int> frames;
  for (int f = *first; f <= *last; ++f) frames.push_back(f);
  return frames;
}

std::optional<std::string> frame_output_path(std::string_view pattern, int frame) {
  std::string out;
  bool found = false;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') {
      out += pattern[i];
      continue;
    }
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      out += '%';
      ++i;
      continue;
    }
    // %d or %0Nd
    size_t j = i + 1;
    int width = 0;
    if (j + 1 < pattern.size() && pattern[j] == '0' && pattern[j + 1] >= '1' && pattern[j + 1] <= '9') {
      width = pattern[j + 1] - '0';
      j += 2;
    }
    if (j >= pattern.size() || pattern[j] != 'd' || found) return std::nullopt;  // not (only) one pattern
    std::string number = std::to_string(frame);
    if (static_cast<int>(number.size()) < width) number.insert(0, width - number.size(), '0');
    out += number;
    found = true;
    i = j;
  }
  if (!found) return std::nullopt;
  return out;
}

}  // namespace glint
