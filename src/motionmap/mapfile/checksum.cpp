#include "motionmap/mapfile/detail/checksum.h"

#include <algorithm>
#include <bit>
#include <cstdio>

#define XXH_INLINE_ALL
#include <xxhash.h>

namespace motionmap::mapfile::detail {

// The canonical forms are little-endian: the bytes in memory are them as they are.
static_assert(std::endian::native == std::endian::little,
              "map file checksums assume a little-endian machine");

struct Hasher::State {
  XXH3_state_t state;
};

Hasher::Hasher() : m(std::make_unique<State>()) {
  XXH3_64bits_reset(&m->state);
}

Hasher::~Hasher() = default;

void Hasher::bytes(const void* data, std::size_t size) {
  if (size > 0) XXH3_64bits_update(&m->state, data, size);
}

void Hasher::strings(const std::vector<std::string>& values) {
  for (const std::string& v : values) bytes(v.c_str(), v.size() + 1);
}

std::uint64_t Hasher::digest() const {
  return XXH3_64bits_digest(&m->state);
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
