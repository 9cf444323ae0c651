#include "glint/accel/huge_pages.h"

#include <mutex>

namespace glint {

namespace {

struct Recycled {
  std::mutex mutex;
  void* buffer = nullptr;
  size_t bytes = 0;  // usable: a multiple of 2 MiB
  int scopes = 0;    // BufferRecycling objects alive
};

Recycled& recycled() {
  static Recycled r;
  return r;
}

}  // namespace

void* take_recycled_buffer(size_t bytes) {
  Recycled& r = recycled();
  void* p = nullptr;
  size_t had = 0;
  {
    std::lock_guard lock(r.mutex);
    if (!r.buffer || r.bytes < bytes) return nullptr;
    p = std::exchange(r.buffer, nullptr);
    had = std::exchange(r.bytes, 0);
  }
#if defined(__linux__)
  if (had > bytes) ::madvise(static_cast<char*>(p) + bytes, had - bytes, MADV_DONTNEED);
#endif
  return p;
}

bool keep_recycled_buffer(void* p, size_t bytes) {
  Recycled& r = recycled();
  void* older = p;
  {
    std::lock_guard lock(r.mutex);
    if (r.scopes == 0 || r.bytes >= bytes) return false;  // none asked for; or the larger one stays
    older = std::exchange(r.buffer, p);
    r.bytes = bytes;
  }
  std::free(older);
  return true;
}

void release_recycled_buffer() {
  Recycled& r = recycled();
  void* p = nullptr;
  {
    std::lock_guard lock(r.mutex);
    p = std::exchange(r.buffer, nullptr);
    r.bytes = 0;
  }
  std::free(p);
}

BufferRecycling::BufferRecycling() {
  Recycled& r = recycled();
  std::lock_guard lock(r.mutex);
  ++r.scopes;
}

BufferRecycling::~BufferRecycling() {
  Recycled& r = recycled();
  bool last = false;
  {
    std::lock_guard lock(r.mutex);
    last = --r.scopes == 0;
  }
  if (last) release_recycled_buffer();
}

}  // namespace glint
