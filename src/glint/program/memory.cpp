// The program's heap, set up before main (glibc only). The kernel of a busy
// virtual machine -- this project's own test machine -- takes tens of
// microseconds for each 4 KiB page a process touches for the first time,
// and a render touches thousands: the scene's document, the scene, the
// accelerator, the image. So glibc's malloc serves blocks of up to 32 MiB
// from its heap and keeps what is freed (the next phase reuses pages already
// there), every thread allocates from it, and it grows once, by 64 MiB ahead,
// advised to the kernel as huge-page memory: where transparent huge pages
// are on ("madvise" mode, Debian's default) it costs one fault per 2 MiB.
// Not where the kernel reports free memory to a hypervisor: there fresh
// 2 MiB pages cost far more than small ones (util/page_policy.h).
// That is the program's choice for its own process (glibc's tunables
// hugetlb=1 and arena_max=1 would make much the same one); the library never
// changes the allocator of the program it is in.
// Measured in docs/performance.md ("SPD scenes").
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "glint/util/page_policy.h"

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
  // One heap for every thread: another thread's would be a fresh mapping of
  // small pages (the accelerator's build threads allocate as much as the
  // main one). The render threads hardly allocate, so they do not wait on it.
  mallopt(M_ARENA_MAX, 1);
  if (!glint::huge_pages_pay()) return;  // the rest only readies the heap for huge pages
  // The program break moved up to a huge page boundary (glibc takes a break
  // moved by someone else as a new start of its heap). Then a block of
  // nearly 2 MiB, kept for good, makes malloc grow the heap now by the block
  // and the pad, and fills the first huge page, whose small pages malloc's
  // bookkeeping has touched: a huge page only backs 2 MiB none of whose small
  // pages is in use yet. What malloc hands out next comes from the huge pages
  // advised here.
  const auto now = reinterpret_cast<uintptr_t>(sbrk(0));
  const uintptr_t first = (now + kHugePage - 1) & ~(kHugePage - 1);
  if (now == static_cast<uintptr_t>(-1) || sbrk(static_cast<intptr_t>(first - now)) == reinterpret_cast<void*>(-1))
    return;
  static void* const first_page = std::malloc(kHugePage - 256);
  const auto after = reinterpret_cast<uintptr_t>(sbrk(0));
  const uintptr_t from = first + kHugePage, to = after & ~(kHugePage - 1);
  if (first_page && to > from) madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE);
}

#else

void set_up_heap() {}

#endif

// Before main, and before anything big is allocated.
const int heap_ready = (set_up_heap(), 0);

}  // namespace
