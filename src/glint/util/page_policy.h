// Whether to ask Linux for 2 MiB pages (transparent huge pages, madvise
// mode) for big buffers: one page fault per 2 MiB instead of 512, and fewer
// TLB misses in a big mesh. Not on a virtual machine whose kernel reports
// free memory to the host (virtio-balloon free page reporting): the host
// takes back the large free blocks, which are where 2 MiB pages come from,
// and must supply them again at their first touch, while 4 KiB pages mostly
// come from smaller free blocks the guest still holds. Measured on such a
// machine (docs/performance.md, "Page size"): the 1M terrain after a
// POV-Ray run 1.04-1.19 s with huge pages, 0.54-0.59 s without. Depends on
// nothing else of glint.
#pragma once

namespace glint {

// GLINT_HUGE_PAGES: "1" or "always" asks for huge pages, "0" or "never"
// does not; unset (or anything else): decided by reports_free_pages.
enum class HugePagePolicy { automatic, always, never };
HugePagePolicy huge_page_policy(const char* env_value);

// Whether a virtio balloon device under `virtio_devices` (sysfs) has
// negotiated free page reporting (VIRTIO_BALLOON_F_REPORTING, feature bit
// 5). Reads virtio0 .. virtio63; allocates nothing. (Other hypervisors'
// balloons, such as Hyper-V's, are not looked for.)
bool reports_free_pages(const char* virtio_devices = "/sys/bus/virtio/devices");

// The process's answer, decided on the first call and the same from then
// on. Thread-safe; allocates nothing, so the program's heap setup may ask it
// before main.
bool huge_pages_pay();

}  // namespace glint
