// HugePageVector: a std::vector whose large buffers ask Linux for 2 MiB
// pages (transparent huge pages, madvise mode). A ray through a big mesh
// touches nodes and leaf blocks scattered over hundreds of megabytes; with
// 4 KiB pages nearly every one of those loads also misses the TLB. Asked
// only where they pay (util/page_policy.h): on some virtual machines a
// fresh 2 MiB page costs far more than its 512 small ones.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "glint/util/page_policy.h"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace glint {

inline constexpr size_t kHugePageBytes = size_t{2} << 20;
// Smaller buffers are not worth a 2 MiB-aligned block of their own.
inline constexpr size_t kHugePageThreshold = size_t{4} << 20;

// The big buffers of a render come one after another: the mesh file's
// bytes, then the build's boxes, its binary tree, the wide nodes, the leaf
// blocks. While a BufferRecycling lives, each freed one is kept (one at a
// time, the largest) for the next to reuse: its pages are already there,
// where fresh ones cost a fault and the kernel's zeroing each (about 0.2 ms
// a MB here). Part of a kept buffer beyond what the next one asks for is
// given back (MADV_DONTNEED), so it holds no more memory than asked.
// build_accelerator opens one for the build and releases the kept buffer at
// its end; the glint program opens one around loading the scene, so the
// mesh file's bytes serve the build. Without one, buffers are freed as
// usual (a library user's process keeps nothing).
// Sizes are rounded to 2 MiB; take/keep return nullptr / false when unused.
void* take_recycled_buffer(size_t bytes);
bool keep_recycled_buffer(void* p, size_t bytes);
void release_recycled_buffer();
class BufferRecycling {
 public:
  BufferRecycling();
  ~BufferRecycling();  // the last one releases the kept buffer
  BufferRecycling(const BufferRecycling&) = delete;
  BufferRecycling& operator=(const BufferRecycling&) = delete;
};

template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(size_t n) {
    if (n > static_cast<size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    const size_t bytes = n * sizeof(T);
    if (bytes < kHugePageThreshold) return static_cast<T*>(::operator new(bytes, std::align_val_t(alignof(T))));
    const size_t rounded = (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
    if (void* recycled = take_recycled_buffer(rounded)) return static_cast<T*>(recycled);
    void* p = std::aligned_alloc(kHugePageBytes, rounded);
    if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    // A hint (without THP the pages stay small), given where it pays.
    if (huge_pages_pay()) ::madvise(p, rounded, MADV_HUGEPAGE);
#endif
    return static_cast<T*>(p);
  }
  // Elements made without arguments are default-initialized, not zeroed:
  // the buffers here (BVH nodes, triangle blocks) are written in full by
  // their builders, and zeroing 40 MB first only to overwrite it costs a
  // pass over memory.
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  void deallocate(T* p, size_t n) noexcept {
    const size_t bytes = n * sizeof(T);
    if (bytes < kHugePageThreshold) ::operator delete(p, std::align_val_t(alignof(T)));
    else if (!keep_recycled_buffer(p, (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes)) std::free(p);
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept {
    return true;
  }
};

template <class T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace glint
