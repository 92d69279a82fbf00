#include "core/content_hash.h"

#include <openssl/evp.h>

#include <bit>

#include "absl/strings/escaping.h"

namespace fitbase::core {

// Hashes are defined over little-endian bytes; every platform we build for is little-endian.
static_assert(std::endian::native == std::endian::little);

struct ContentHash::State {
  EVP_MD_CTX* context = EVP_MD_CTX_new();
  ~State() { EVP_MD_CTX_free(context); }
};

ContentHash::ContentHash() : state_(std::make_unique<State>()) {
  EVP_DigestInit_ex(state_->context, EVP_sha256(), nullptr);
}

ContentHash::~ContentHash() = default;

void ContentHash::Update(const void* data, size_t size) {
  EVP_DigestUpdate(state_->context, data, size);
}

ContentHash& ContentHash::Add(absl::string_view bytes) {
  const uint64_t size = bytes.size();
  Update(&size, sizeof(size));
  Update(bytes.data(), bytes.size());
  return *this;
}

ContentHash& ContentHash::Add(std::span<const float> values) {
  return Add(absl::string_view(reinterpret_cast<const char*>(values.data()), values.size_bytes()));
}

ContentHash& ContentHash::Add(double value) {
  return Add(absl::string_view(reinterpret_cast<const char*>(&value), sizeof(value)));
}

ContentHash& ContentHash::Add(int64_t value) {
  return Add(absl::string_view(reinterpret_cast<const char*>(&value), sizeof(value)));
}

std::string ContentHash::HexDigest() {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int size = 0;
  EVP_DigestFinal_ex(state_->context, digest, &size);
  return absl::BytesToHexString(absl::string_view(reinterpret_cast<const char*>(digest), size));
}

std::string Sha256Hex(absl::string_view bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int size = 0;
  EVP_Digest(bytes.data(), bytes.size(), digest, &size, EVP_sha256(), nullptr);
  return absl::BytesToHexString(absl::string_view(reinterpret_cast<const char*>(digest), size));
}

}  // namespace fitbase::core
