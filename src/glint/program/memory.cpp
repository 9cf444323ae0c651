// The program's heap, set up before main (glibc only). The kernel of a busy
// virtual machine -- this project's own test machine -- takes tens of
// microseconds for each 4 KiB page a process touches for the first time,
// and a render touches thousands: the scene's document, the scene, the
// accelerator, the image. So glibc's malloc serves blocks of up to 32 MiB
// from its heap and keeps what is freed (the next phase reuses pages already
// there), and the heap grows once, by 64 MiB ahead, advised to the kernel as
// huge-page memory: where transparent huge pages are on ("madvise" mode,
// Debian's default) it costs one fault per 2 MiB. That is the program's
// choice for its own process, as GLIBC_TUNABLES=glibc.malloc.hugetlb=1 would
// make it; the library never changes the allocator of the program it is in.
// Measured in docs/performance.md ("SPD scenes").
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#if defined(__GLIBC__) && defined(__linux__)
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace {

#if defined(__GLIBC__) && defined(__linux__) && defined(MADV_HUGEPAGE)

constexpr size_t kHugePage = size_t{2} << 20;
constexpr size_t kHeapAhead = size_t{64} << 20;

void set_up_heap() {
  // 32 MiB is the largest threshold glibc takes; bigger blocks (a big mesh's
  // arrays) are still mapped on their own (and some ask for huge pages
  // themselves: accel/huge_pages.h).
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_TOP_PAD, static_cast<int>(kHeapAhead));
  // A block bigger than what is left at the top makes malloc grow the heap
  // now, by the block and the pad; freed, it stays there as free space.
  const auto before = reinterpret_cast<uintptr_t>(sbrk(0));
  void* grow = std::malloc(size_t{1} << 20);
  std::free(grow);
  const auto after = reinterpret_cast<uintptr_t>(sbrk(0));
  const uintptr_t first = (before + kHugePage - 1) & ~(kHugePage - 1), last = after & ~(kHugePage - 1);
  if (grow && last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}

#else

void set_up_heap() {}

#endif

// Before main, and before anything big is allocated.
const int heap_ready = (set_up_heap(), 0);

}  // namespace
