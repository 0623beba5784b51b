#pragma once
// What the machine has: memory available to a new allocation, and this process's peak so far. For
// estimating a computation's memory before allocating it, and for --verbose reports.
#include <cstdint>
#include <optional>
#include <string>

namespace motionmap {

/// Bytes the kernel says can be allocated without swapping (MemAvailable of /proc/meminfo,
/// capped by a cgroup v2 memory.max when one is set); nullopt where neither can be read.
std::optional<std::int64_t> available_memory();

/// The largest resident set size of this process so far, in bytes (getrusage).
std::int64_t peak_memory();

/// Gives the memory the process has freed back to the system where the allocator keeps it (glibc:
/// malloc_trim; freed blocks of a few MB inside its heaps otherwise stay resident). For after
/// freeing a large amount of memory in many blocks, before allocating anew.
void release_freed_memory();

/// "58 GB", "640 MB", "12 kB": two significant digits at most, decimal units.
std::string format_bytes(double bytes);

}  // namespace motionmap
