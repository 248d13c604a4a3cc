// Memory checks before large allocations (issue 8): an input whose estimated memory exceeds
// what this machine has is rejected with the estimate, before anything is allocated, instead
// of failing later with std::bad_alloc or being killed by the kernel.
#pragma once

#include <cstdint>
#include <string>

namespace asperity::app {

// Memory the checks may plan with, in bytes: the environment variable ASPERITY_MEMORY_GIB if set
// (a positive number: to keep a run within a share of a machine, and for tests), otherwise the
// physical memory of this machine (0 if it cannot be read).
std::uint64_t physical_memory_bytes();

// Throws std::invalid_argument "<what> needs about X GiB of memory (<how>), more than the Y GiB
// this machine has" when `bytes` exceeds 90% of physical_memory_bytes() (or is not finite).
// `what` names the input (key, flag or file), so the message says what to change.
void check_fits_in_memory(const std::string& what, double bytes, const std::string& how);

// Peak resident memory of this process so far, in bytes (getrusage: ru_maxrss; 0 if it cannot be
// read). A sweep running one point at a time in order of growing contact reports each point's
// own peak; points run side by side share one.
std::uint64_t peak_memory_bytes();

// Free disk space of the file system holding `dir` (or its nearest existing parent), in bytes:
// the environment variable ASPERITY_DISK_GIB if set (a positive number: for tests), otherwise
// what statvfs gives an unprivileged writer (0 if it cannot be read).
std::uint64_t free_disk_bytes(const std::string& dir);

// Throws std::invalid_argument "<what> needs about X GiB of disk in <dir> (<how>), more than the
// Y GiB free there" when `bytes` exceeds 95% of free_disk_bytes(dir).
void check_fits_on_disk(const std::string& what, const std::string& dir, double bytes,
                        const std::string& how);

}  // namespace asperity::app
