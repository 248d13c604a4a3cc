// Memory checks before large allocations; see memory.hpp.
#include "asperity/apps/common/memory.hpp"

#include <sys/resource.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

namespace asperity::app {

namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

// A size in GiB from the environment variable `name`, if it is set.
std::optional<std::uint64_t> gib_from_environment(const char* name) {
  const char* text = std::getenv(name);
  if (!text) return std::nullopt;
  char* end = nullptr;
  const double gib = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(gib) || !(gib > 0.0) || gib > 1e9) {
    throw std::invalid_argument(std::string(name) + " = '" + text +
                                "': allowed: a positive number of GiB");
  }
  return static_cast<std::uint64_t>(gib * kGiB);
}

}  // namespace

std::uint64_t physical_memory_bytes() {
  if (const auto gib = gib_from_environment("ASPERITY_MEMORY_GIB")) return *gib;
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 0;
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page);
}

std::uint64_t peak_memory_bytes() {
  rusage usage{};
  if (::getrusage(RUSAGE_SELF, &usage) != 0 || usage.ru_maxrss < 0) return 0;
  return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024;  // kilobytes on Linux
}

void check_fits_in_memory(const std::string& what, double bytes, const std::string& how) {
  const double have = static_cast<double>(physical_memory_bytes());
  // Leave room for the rest of the process and the system: past 90% the kernel kills.
  if (have <= 0.0 || (std::isfinite(bytes) && bytes <= 0.9 * have)) return;
  char buf[256];
  if (std::isfinite(bytes)) {
    std::snprintf(buf, sizeof buf,
                  " needs about %.3g GiB of memory (%s), more than the %.3g GiB this machine has",
                  bytes / kGiB, how.c_str(), have / kGiB);
  } else {
    std::snprintf(buf, sizeof buf,
                  " needs more memory than can be counted (%s); this machine has %.3g GiB",
                  how.c_str(), have / kGiB);
  }
  throw std::invalid_argument(what + buf);
}

std::uint64_t free_disk_bytes(const std::string& dir) {
  if (const auto gib = gib_from_environment("ASPERITY_DISK_GIB")) return *gib;
  std::filesystem::path p = std::filesystem::absolute(dir);
  std::error_code ec;
  while (!std::filesystem::exists(p, ec) && p.has_parent_path() && p != p.parent_path())
    p = p.parent_path();
  struct statvfs fs {};
  if (::statvfs(p.c_str(), &fs) != 0) return 0;
  return static_cast<std::uint64_t>(fs.f_bavail) * static_cast<std::uint64_t>(fs.f_frsize);
}

void check_fits_on_disk(const std::string& what, const std::string& dir, double bytes,
                        const std::string& how) {
  const double have = static_cast<double>(free_disk_bytes(dir));
  if (have <= 0.0 || (std::isfinite(bytes) && bytes <= 0.95 * have)) return;
  char buf[400];
  std::snprintf(buf, sizeof buf,
                " needs about %.3g GiB of disk in %s (%s), more than the %.3g GiB free there",
                bytes / kGiB, dir.c_str(), how.c_str(), have / kGiB);
  throw std::invalid_argument(what + buf);
}

}  // namespace asperity::app
