// Frames of an animation on the command line: which frames to render
// (`--frames 0-119`) and the output name of each (`out_%04d.png`).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace glint {

// "N" or "A-B" (inclusive), every frame in [0, frame_count); glint::Error otherwise.
std::vector<int> parse_frame_range(std::string_view text, int frame_count);

// The output name for `frame` when `pattern` holds exactly one printf-style
// frame number (%d or %0Nd, N ≤ 9; %% is a literal percent sign); nullopt
// when it holds none, and then the name is used as it is.
std::optional<std::string> frame_output_path(std::string_view pattern, int frame);

}  // namespace glint
