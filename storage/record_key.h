#ifndef FITBASE_STORAGE_RECORD_KEY_H_
#define FITBASE_STORAGE_RECORD_KEY_H_

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace fitbase::storage {

// Ids (tenants, garments, sizes, content ids, builds, ...) are 1..kMaxIdBytes bytes of
// printable ASCII without space (0x21..0x7E): they appear verbatim in messages and logs.
inline constexpr size_t kMaxIdBytes = 256;

// Ends every id inside a key. Ids never contain it and it sorts below every id byte, so keys
// compare like the tuples of their ids, and the key of a record's first k ids is exactly the
// prefix its siblings share (a tenant's garments, a build's tasks, a clothing basis's versions).
inline constexpr char kIdTerminator = '\0';

// OK when `id` is a valid id; else INVALID_ARGUMENT naming `field` and what is wrong.
absl::Status ValidateId(absl::string_view field, absl::string_view id);

// One id of a key, with the name errors call it by ("tenant", "garment_id", ...).
struct KeyField {
  absl::string_view name;
  absl::string_view id;
};

// The ids of `fields` in order, each followed by kIdTerminator. The first invalid id is an
// INVALID_ARGUMENT error naming its field.
absl::StatusOr<std::string> EncodeKey(std::initializer_list<KeyField> fields);

// The ids of a key made by EncodeKey, or of the part of one after a prefix made by EncodeKey.
// DATA_LOSS when `key` is not such a key: stored keys are only ever made by EncodeKey.
absl::StatusOr<std::vector<std::string>> DecodeKey(absl::string_view key);

// A version number as 8 big-endian bytes: appended to a key, the versions of that key sort in
// numeric order, so the newest is the last key under the prefix.
std::string EncodeVersion(uint64_t version);

// The inverse of EncodeVersion; DATA_LOSS unless `bytes` is exactly 8 bytes.
absl::StatusOr<uint64_t> DecodeVersion(absl::string_view bytes);

// One clothing basis: the fit of `tenant`'s garment `garment_id` in `size` over the avatar
// basis `avatar_basis_id`, built by `method`. Each publication of it is a new version.
struct ClothingBasisKey {
  std::string tenant;
  std::string garment_id;
  std::string size;
  std::string avatar_basis_id;
  std::string method;
};

// EncodeKey over the key's fields in declaration order (tenant first).
absl::StatusOr<std::string> EncodeClothingBasisKey(const ClothingBasisKey& key);

// "clothing basis (tenant 't', garment 'g', size 'M', avatar basis 'a', method 'm')", for
// messages.
std::string DescribeClothingBasisKey(const ClothingBasisKey& key);

}  // namespace fitbase::storage

#endif  // FITBASE_STORAGE_RECORD_KEY_H_
