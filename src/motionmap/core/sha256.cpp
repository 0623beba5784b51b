#include "motionmap/core/sha256.h"

// OpenSSL 3 deprecates the SHA256_* functions in favour of EVP, whose digests keep an error queue
// per thread: on the thread pool's workers, alive until the process exits, AddressSanitizer's
// leak check reports each one. These compute the same digest with the same code (SHA extensions
// included) and keep no state outside the context.
#define OPENSSL_SUPPRESS_DEPRECATED
#include <openssl/sha.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"

namespace motionmap {

struct Sha256::Context {
  SHA256_CTX context;
};

Sha256::Sha256() : m_context(std::make_unique<Context>()) {
  SHA256_Init(&m_context->context);
}

Sha256::~Sha256() = default;

void Sha256::update(const void* data, std::size_t size) {
  SHA256_Update(&m_context->context, data, size);
}

void Sha256::update(std::string_view bytes) {
  update(bytes.data(), bytes.size());
}

std::array<std::uint8_t, 32> Sha256::digest() {
  if (!m_finished) {
    SHA256_Final(m_digest.data(), &m_context->context);
    m_finished = true;
  }
  return m_digest;
}

std::string Sha256::hex() {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  for (const std::uint8_t byte : digest()) {
    out += kDigits[byte >> 4];
    out += kDigits[byte & 15];
  }
  return out;
}

std::string sha256_hex(std::string_view bytes) {
  Sha256 h;
  h.update(bytes);
  return h.hex();
}

std::string sha256_file(const std::string& path) {
  std::ifstream in = open_file(path);
  Sha256 h;
  std::vector<char> buffer(std::size_t(1) << 20);
  while (in) {
    in.read(buffer.data(), std::streamsize(buffer.size()));
    h.update(buffer.data(), std::size_t(in.gcount()));
  }
  if (in.bad()) throw Error(path + ": error: cannot read: " + std::strerror(errno));
  return h.hex();
}

}  // namespace motionmap
