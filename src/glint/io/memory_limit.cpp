#include "glint/io/memory_limit.h"

#include <unistd.h>

#include <cstdio>

namespace glint {

size_t default_memory_budget() {
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGE_SIZE);
  const double memory = pages > 0 && page_size > 0 ? static_cast<double>(pages) * page_size : 8.0 * (1 << 30);
  return static_cast<size_t>(memory / 2);
}

std::string format_bytes(double bytes) {
  char buf[32];
  if (bytes >= 1 << 30) std::snprintf(buf, sizeof buf, "%.3g GiB", bytes / (1 << 30));
  else if (bytes >= 1 << 20) std::snprintf(buf, sizeof buf, "%.3g MiB", bytes / (1 << 20));
  else if (bytes >= 1 << 10) std::snprintf(buf, sizeof buf, "%.3g KiB", bytes / (1 << 10));
  else std::snprintf(buf, sizeof buf, "%.0f B", bytes);
  return buf;
}

std::string exceeds_budget(double bytes, size_t budget) {
  if (bytes <= static_cast<double>(budget)) return "";
  // Say it in the machine's terms when the budget is the machine's.
  if (budget == default_memory_budget())
    return "needs " + format_bytes(bytes) + ", more than half of this machine's " + format_bytes(2.0 * budget) +
           " of memory";
  return "needs " + format_bytes(bytes) + ", more than the memory budget of " +
         format_bytes(static_cast<double>(budget));
}

}  // namespace glint
