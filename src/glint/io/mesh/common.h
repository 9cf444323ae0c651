// Small helpers every mesh reader uses: errors naming the file, counts and
// name lists in messages. Internal to io/ (not installed).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "glint/error.h"
#include "glint/math/vec3.h"

namespace glint::mesh_io {

[[noreturn]] void fail(const std::string& file, const std::string& message, int line = 0, int column = 0);

std::string plural(size_t n, const char* singular, const char* plural_form);

std::string lower(std::string_view s);

std::string with_line(const std::string& file, int line);

// Lists up to three names, then "and N more".
std::string name_list(const std::vector<std::string>& names);

// A count as a whole number, also beyond 64 bits ("4000000000", "1e+300").
std::string format_count(double n);

inline bool is_finite(const Vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// An unsigned integer of `size` bytes (PLY data, GLB headers).
uint64_t read_binary_uint(const unsigned char* p, size_t size, bool big_endian);

}  // namespace glint::mesh_io
