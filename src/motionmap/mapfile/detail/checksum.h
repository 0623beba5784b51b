#pragma once
// The map file's content checksums (docs/map-file.md, layout 3), of each dataset's values and of
// each object's attributes in a canonical form that does not depend on how HDF5 stored them. The
// checksum of N bytes is XXH3-64 (Debian's libxxhash, compiled in from its header) of the XXH3-64
// digests (8 bytes each, little-endian) of its consecutive blocks of kChecksumBlock bytes (the
// last one shorter): blocks hashed in parallel, so that checking a model of gigabytes adds little
// to reading it. The canonical forms:
//   float datasets:  the values as little-endian float64, row-major;
//   integer ones:    the values as little-endian int32;
//   string ones:     each string's bytes followed by one NUL;
//   attributes:      for each attribute but the checksums, by name in byte order: the name, NUL,
//                    then 's' + the text + NUL, 'i' + the value as little-endian int64, or 'f' +
//                    the value as little-endian float64.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace motionmap::mapfile::detail {

/// The attribute on every dataset holding its checksum (uint64).
inline constexpr const char* kChecksumAttribute = "xxh3";
/// The attribute on every object with attributes holding their checksum (uint64).
inline constexpr const char* kAttributesChecksumAttribute = "attributes_xxh3";
/// The root attribute naming every dataset written, separated by spaces: a dataset whose link a
/// damaged file lost is missing, not taken for an optional one left out.
inline constexpr const char* kDatasetsAttribute = "datasets";

/// The block size of the checksums: 1 MiB.
inline constexpr std::size_t kChecksumBlock = std::size_t(1) << 20;

/// A checksum fed piece by piece (whole blocks hashed in parallel).
class Hasher {
 public:
  Hasher() = default;
  Hasher(const Hasher&) = delete;
  Hasher& operator=(const Hasher&) = delete;

  void bytes(const void* data, std::size_t size);
  void doubles(const double* values, std::size_t count) { bytes(values, count * sizeof(double)); }
  void int32s(const std::int32_t* values, std::size_t count) {
    bytes(values, count * sizeof(std::int32_t));
  }
  /// Each string's bytes and a NUL.
  void strings(const std::vector<std::string>& values);
  std::uint64_t digest() const;

 private:
  std::vector<std::uint64_t> m_blocks;  // digests of the whole blocks so far
  std::string m_partial;                // the bytes after them (less than a block)
};

/// One attribute's value as the attributes' checksum reads it.
struct AttributeValue {
  std::string name;
  char kind = 's';    ///< 's' text, 'i' integer, 'f' float
  std::string bytes;  ///< the text, or the value's 8 little-endian bytes
};

/// The checksum of an object's attributes (the checksum attributes themselves left out).
std::uint64_t attributes_checksum(std::vector<AttributeValue> attributes);

/// `digest` as 16 hexadecimal digits, for messages.
std::string hex_digest(std::uint64_t digest);

}  // namespace motionmap::mapfile::detail
