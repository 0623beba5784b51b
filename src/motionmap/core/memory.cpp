#include "motionmap/core/memory.h"

#include <sys/resource.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace motionmap {

std::optional<std::int64_t> available_memory() {
  std::optional<std::int64_t> bytes;
  std::ifstream meminfo("/proc/meminfo");
  std::string line;
  while (std::getline(meminfo, line)) {
    std::istringstream in(line);
    std::string key;
    std::int64_t kib = 0;
    if (in >> key >> kib && key == "MemAvailable:") {
      bytes = kib * 1024;
      break;
    }
  }
  std::ifstream limit_file("/sys/fs/cgroup/memory.max");
  std::ifstream usage_file("/sys/fs/cgroup/memory.current");
  std::int64_t limit = 0, usage = 0;
  if (limit_file >> limit && usage_file >> usage && limit > usage) {
    bytes = bytes ? std::min(*bytes, limit - usage) : limit - usage;
  }
  return bytes;
}

std::int64_t peak_memory() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::int64_t>(usage.ru_maxrss) * 1024;  // kilobytes on Linux
}

void release_freed_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

std::string format_bytes(double bytes) {
  const char* units[] = {"B", "kB", "MB", "GB", "TB"};
  int u = 0;
  while (bytes >= 1000.0 && u < 4) {
    bytes /= 1000.0;
    ++u;
  }
  char text[32];
  std::snprintf(text, sizeof text, bytes < 10.0 && u > 0 ? "%.1f %s" : "%.0f %s", bytes, units[u]);
  return text;
}

}  // namespace motionmap
