#include "motionmap/core/sha256.h"

#include <openssl/evp.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"

namespace motionmap {

struct Sha256::Context {
  EVP_MD_CTX* context = EVP_MD_CTX_new();
  ~Context() { EVP_MD_CTX_free(context); }
};

namespace {

// OpenSSL fails only when it cannot allocate or lacks the algorithm: no input of ours does it.
void check(int ok, const char* what) {
  if (ok != 1) throw Error(std::string("SHA-256: OpenSSL's ") + what + " failed");
}

}  // namespace

Sha256::Sha256() : m_context(std::make_unique<Context>()) {
  if (!m_context->context) throw Error("SHA-256: OpenSSL could not make a digest context");
  check(EVP_DigestInit_ex(m_context->context, EVP_sha256(), nullptr), "EVP_DigestInit_ex");
}

Sha256::~Sha256() = default;

void Sha256::update(const void* data, std::size_t size) {
  check(EVP_DigestUpdate(m_context->context, data, size), "EVP_DigestUpdate");
}

void Sha256::update(std::string_view bytes) {
  update(bytes.data(), bytes.size());
}

std::array<std::uint8_t, 32> Sha256::digest() {
  if (!m_finished) {
    unsigned int size = 0;
    check(EVP_DigestFinal_ex(m_context->context, m_digest.data(), &size), "EVP_DigestFinal_ex");
    if (size != m_digest.size()) throw Error("SHA-256: OpenSSL gave a digest of another size");
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
