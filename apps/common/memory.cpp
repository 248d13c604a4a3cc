// Memory checks before large allocations; see memory.hpp.
#include "common/memory.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace asperity::app {

std::uint64_t physical_memory_bytes() {
  if (const char* text = std::getenv("ASPERITY_MEMORY_GIB")) {
    char* end = nullptr;
    const double gib = std::strtod(text, &end);
    if (end == text || *end != '\0' || !std::isfinite(gib) || !(gib > 0.0) || gib > 1e9) {
      throw std::invalid_argument(std::string("ASPERITY_MEMORY_GIB = '") + text +
                                  "': allowed: a positive number of GiB");
    }
    return static_cast<std::uint64_t>(gib * 1024.0 * 1024.0 * 1024.0);
  }
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 0;
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page);
}

void check_fits_in_memory(const std::string& what, double bytes, const std::string& how) {
  const double have = static_cast<double>(physical_memory_bytes());
  // Leave room for the rest of the process and the system: past 90% the kernel kills.
  if (have <= 0.0 || (std::isfinite(bytes) && bytes <= 0.9 * have)) return;
  constexpr double GiB = 1024.0 * 1024.0 * 1024.0;
  char buf[256];
  if (std::isfinite(bytes)) {
    std::snprintf(buf, sizeof buf,
                  " needs about %.3g GiB of memory (%s), more than the %.3g GiB this machine has",
                  bytes / GiB, how.c_str(), have / GiB);
  } else {
    std::snprintf(buf, sizeof buf,
                  " needs more memory than can be counted (%s); this machine has %.3g GiB",
                  how.c_str(), have / GiB);
  }
  throw std::invalid_argument(what + buf);
}

}  // namespace asperity::app
