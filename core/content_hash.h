#ifndef FITBASE_CORE_CONTENT_HASH_H_
#define FITBASE_CORE_CONTENT_HASH_H_

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include "absl/strings/string_view.h"

namespace fitbase::core {

// SHA-256 over a sequence of fields, for content-addressed ids. Each field is written with
// its length first, so ("ab", "c") and ("a", "bc") hash differently.
class ContentHash {
 public:
  ContentHash();
  ~ContentHash();
  ContentHash(const ContentHash&) = delete;
  ContentHash& operator=(const ContentHash&) = delete;

  ContentHash& Add(absl::string_view bytes);
  ContentHash& Add(std::span<const float> values);
  ContentHash& Add(double value);
  ContentHash& Add(int64_t value);

  // Lower-case hex digest; the hash cannot be extended afterwards.
  std::string HexDigest();

 private:
  void Update(const void* data, size_t size);

  struct State;
  std::unique_ptr<State> state_;
};

// SHA-256 of `bytes` alone, as lower-case hex: unlike ContentHash, the digest any other tool
// (`sha256sum`, a script provisioning API keys) computes for the same bytes.
std::string Sha256Hex(absl::string_view bytes);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_CONTENT_HASH_H_
