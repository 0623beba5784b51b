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
// OpenSSL's libcrypto computes it (with the CPU's SHA extensions where it has them: ~1.6 GB/s
// on this project's build machine, against ~0.2 GB/s for a portable implementation).
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace motionmap {

/// Incremental SHA-256: update() any number of times, then digest() or hex() once.
class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;

  /// Appends `bytes` to the message.
  void update(std::string_view bytes);
  void update(const void* data, std::size_t size);

  /// The 32-byte digest of everything passed to update(). Ends the message: call it (or hex())
  /// once, and no update() after it.
  std::array<std::uint8_t, 32> digest();
  /// digest() as 64 lowercase hexadecimal digits, as `sha256sum` prints it.
  std::string hex();

 private:
  struct Context;  // OpenSSL's digest context
  std::unique_ptr<Context> m_context;
  std::array<std::uint8_t, 32> m_digest{};
  bool m_finished = false;
};

/// SHA-256 of `bytes`, as 64 lowercase hexadecimal digits.
std::string sha256_hex(std::string_view bytes);

/// SHA-256 of the file at `path` (read in blocks, whatever its size), as 64 lowercase
/// hexadecimal digits. @throws Error naming the path and the system's reason if it cannot be
/// opened or read, or is a directory.
std::string sha256_file(const std::string& path);

}  // namespace motionmap
