#include "glint/util/page_policy.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>

#if defined(__linux__)
#include <fcntl.h>
#include <unistd.h>
#endif

namespace glint {

namespace {

constexpr int kVirtioBalloonDevice = 5;     // the virtio device id of a memory balloon
constexpr int kBalloonReportingBit = 5;     // VIRTIO_BALLOON_F_REPORTING
constexpr int kVirtioDevicesSearched = 64;  // virtio0 .. virtio63

// The first bytes of a small sysfs file into `out` (NUL-terminated); false
// when it cannot be read. No allocation (before main, the heap is being set up).
bool read_small_file(const char* path, char* out, size_t size) {
#if defined(__linux__)
  const int fd = ::open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const ssize_t n = ::read(fd, out, size - 1);
  ::close(fd);
  if (n <= 0) return false;
  out[n] = '\0';
  return true;
#else
  (void)path;
  (void)out;
  (void)size;
  return false;
#endif
}

}  // namespace

HugePagePolicy huge_page_policy(const char* env_value) {
  if (!env_value) return HugePagePolicy::automatic;
  if (std::strcmp(env_value, "1") == 0 || std::strcmp(env_value, "always") == 0) return HugePagePolicy::always;
  if (std::strcmp(env_value, "0") == 0 || std::strcmp(env_value, "never") == 0) return HugePagePolicy::never;
  return HugePagePolicy::automatic;
}

bool reports_free_pages(const char* virtio_devices) {
  char path[512], text[160];
  for (int i = 0; i < kVirtioDevicesSearched; ++i) {
    // sysfs: `device` holds the id ("0x0005"), `features` one '0'/'1' a
    // feature bit, bit 0 first, as the driver negotiated them.
    std::snprintf(path, sizeof path, "%s/virtio%d/device", virtio_devices, i);
    if (!read_small_file(path, text, sizeof text)) continue;
    if (std::strtol(text, nullptr, 16) != kVirtioBalloonDevice) continue;
    std::snprintf(path, sizeof path, "%s/virtio%d/features", virtio_devices, i);
    if (read_small_file(path, text, sizeof text) && std::strlen(text) > kBalloonReportingBit &&
        text[kBalloonReportingBit] == '1')
      return true;
  }
  return false;
}

bool huge_pages_pay() {
  static const bool pay = [] {
#if defined(__linux__)
    switch (huge_page_policy(std::getenv("GLINT_HUGE_PAGES"))) {
      case HugePagePolicy::always:
        return true;
      case HugePagePolicy::never:
        return false;
      case HugePagePolicy::automatic:
        break;
    }
    return !reports_free_pages();
#else
    return false;
#endif
  }();
  return pay;
}

}  // namespace glint
