// Small helpers every mesh reader uses: errors naming the file, counts and
// name lists in messages. Internal to io/ (not installed).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
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

// Asks Linux for 2 MiB pages for the whole 2 MiB blocks inside
// [data, data + bytes) (transparent huge pages, madvise mode); a hint, and
// nothing for less than 4 MiB or where huge pages do not pay
// (util/page_policy.h). Only pages not touched yet become huge.
void advise_huge_pages(const void* data, size_t bytes);

// `v` (empty, or holding what it keeps) resized to n value-initialised
// elements, in fresh memory advised into 2 MiB pages before it is first
// touched. The large arrays of a mesh load: every fresh 4 KiB page costs a
// page fault on first touch, about 5 us each on the virtual machines
// measured (a 1M-triangle OBJ's arrays made some 30,000 of them, most of
// its load); a 2 MiB page is one fault for 512 of them.
template <class T>
void resize_in_huge_pages(std::vector<T>& v, size_t n) {
  if (n <= v.capacity()) {
    v.resize(n);
    return;
  }
  std::vector<T> fresh;
  fresh.reserve(n);
  advise_huge_pages(fresh.data(), n * sizeof(T));
  fresh.assign(v.begin(), v.end());
  fresh.resize(n);
  v.swap(fresh);
}

// `v` copied into memory of its exact size (advised as above) when the
// capacity it grew to holds more than 1/256 unused: the arrays a mesh keeps
// for the whole render should not carry a reader's push_back slack.
template <class T>
void fit_capacity(std::vector<T>& v) {
  if (v.capacity() - v.size() <= v.capacity() / 256) return;
  std::vector<T> exact;
  exact.reserve(v.size());
  advise_huge_pages(exact.data(), v.size() * sizeof(T));
  exact.assign(v.begin(), v.end());
  v.swap(exact);
}

// Runs f(0) .. f(n - 1) on up to `threads` threads (0: one per hardware
// thread); each f(i) must write only its own results. The first exception
// thrown is rethrown once all are done.
void run_parallel(size_t n, size_t threads, const std::function<void(size_t)>& f);

// An unsigned integer of `size` bytes (PLY data, GLB headers).
uint64_t read_binary_uint(const unsigned char* p, size_t size, bool big_endian);

}  // namespace glint::mesh_io
