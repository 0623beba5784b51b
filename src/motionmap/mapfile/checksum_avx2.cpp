// XXH3-64 built for AVX2 (this file alone is compiled with -mavx2 on x86-64, see
// src/motionmap/CMakeLists.txt): the same hash as the default SSE2 build, twice as fast. Called by
// checksum.cpp only on a processor that has AVX2.
#if defined(__x86_64__) && defined(__AVX2__)
#include <cstddef>
#include <cstdint>

#define XXH_INLINE_ALL
#include <xxhash.h>

namespace motionmap::mapfile::detail {

std::uint64_t xxh3_avx2(const void* data, std::size_t size) {
  return XXH3_64bits(data, size);
}

}  // namespace motionmap::mapfile::detail
#endif
