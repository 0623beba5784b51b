#pragma once
// SHA-256 (FIPS 180-4) of bytes and of files, for naming a file's content: a map file records
// the hash of every clip it was made from, so a later reader can tell whether a clip changed.
//
//   motionmap::Sha256 h;
//   h.update(bytes_a);
//   h.update(bytes_b);
//   std::string hex = h.hex();                            // 64 lowercase hex digits
//   std::string same = motionmap::sha256_file("64_08.bvh");  // what `sha256sum` prints
//
// Not a security boundary: a plain, portable implementation (no CPU extensions).
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace motionmap {

/// Incremental SHA-256: update() any number of times, then digest() or hex() once.
class Sha256 {
 public:
  Sha256();

  /// Appends `bytes` to the message.
  void update(std::string_view bytes);
  void update(const void* data, std::size_t size);

  /// The 32-byte digest of everything passed to update(). Ends the message: call it (or hex())
  /// once, and no update() after it.
  std::array<std::uint8_t, 32> digest();
  /// digest() as 64 lowercase hexadecimal digits, as `sha256sum` prints it.
  std::string hex();

 private:
  void compress(const std::uint8_t* block);

  std::array<std::uint32_t, 8> m_state;
  std::array<std::uint8_t, 64> m_block{};
  std::size_t m_used = 0;      ///< bytes waiting in m_block
  std::uint64_t m_length = 0;  ///< message length so far, in bytes
  bool m_finished = false;
};

/// SHA-256 of `bytes`, as 64 lowercase hexadecimal digits.
std::string sha256_hex(std::string_view bytes);

/// SHA-256 of the file at `path` (read in blocks, whatever its size), as 64 lowercase
/// hexadecimal digits. @throws Error naming the path and the system's reason if it cannot be
/// opened or read, or is a directory.
std::string sha256_file(const std::string& path);

}  // namespace motionmap
