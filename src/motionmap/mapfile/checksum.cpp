#include "motionmap/mapfile/detail/checksum.h"

#include <algorithm>
#include <bit>
#include <cstdio>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include "motionmap/core/parallel.h"

namespace motionmap::mapfile::detail {

#if defined(__x86_64__) && defined(MOTIONMAP_XXH3_AVX2)
std::uint64_t xxh3_avx2(const void* data, std::size_t size);  // checksum_avx2.cpp
#endif

namespace {

// XXH3-64 of `size` bytes, by the AVX2 build where the processor has it (the same hash).
std::uint64_t xxh3(const void* data, std::size_t size) {
#if defined(__x86_64__) && defined(MOTIONMAP_XXH3_AVX2)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) return xxh3_avx2(data, size);
#endif
  return XXH3_64bits(data, size);
}

}  // namespace

// The canonical forms are little-endian: the bytes in memory are them as they are.
static_assert(std::endian::native == std::endian::little,
              "map file checksums assume a little-endian machine");

void Hasher::bytes(const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  if (!m_partial.empty()) {
    const std::size_t take = std::min(size, kChecksumBlock - m_partial.size());
    m_partial.append(p, take);
    p += take;
    size -= take;
    if (m_partial.size() < kChecksumBlock) return;
    m_blocks.push_back(xxh3(m_partial.data(), m_partial.size()));
    m_partial.clear();
  }
  const std::size_t whole = size / kChecksumBlock;
  if (whole > 0) {
    const std::size_t first = m_blocks.size();
    m_blocks.resize(first + whole);
    const auto hash = [&](int b) {
      m_blocks[first + std::size_t(b)] = xxh3(p + std::size_t(b) * kChecksumBlock, kChecksumBlock);
    };
    if (whole == 1) {
      hash(0);
    } else {
      parallel_for(static_cast<int>(whole), hash);
    }
    p += whole * kChecksumBlock;
    size -= whole * kChecksumBlock;
  }
  m_partial.append(p, size);
}

void Hasher::strings(const std::vector<std::string>& values) {
  for (const std::string& v : values) bytes(v.c_str(), v.size() + 1);
}

std::uint64_t Hasher::digest() const {
  std::vector<std::uint64_t> blocks = m_blocks;
  if (!m_partial.empty()) blocks.push_back(xxh3(m_partial.data(), m_partial.size()));
  return xxh3(blocks.data(), blocks.size() * sizeof(std::uint64_t));
}

std::uint64_t attributes_checksum(std::vector<AttributeValue> attributes) {
  std::sort(attributes.begin(), attributes.end(),
            [](const AttributeValue& a, const AttributeValue& b) { return a.name < b.name; });
  Hasher h;
  for (const AttributeValue& a : attributes) {
    if (a.name == kChecksumAttribute || a.name == kAttributesChecksumAttribute) continue;
    h.bytes(a.name.c_str(), a.name.size() + 1);
    h.bytes(&a.kind, 1);
    h.bytes(a.bytes.data(), a.bytes.size());
    if (a.kind == 's') h.bytes("", 1);
  }
  return h.digest();
}

std::string hex_digest(std::uint64_t digest) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(digest));
  return text;
}

}  // namespace motionmap::mapfile::detail
