#include "storage/record_key.h"

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace fitbase::storage {

absl::Status ValidateId(absl::string_view field, absl::string_view id) {
  if (id.empty()) return absl::InvalidArgumentError(absl::StrCat(field, " is empty"));
  if (id.size() > kMaxIdBytes) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, " is ", id.size(), " bytes, more than ", kMaxIdBytes));
  }
  for (size_t i = 0; i < id.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(id[i]);
    if (c < 0x21 || c > 0x7E) {
      // The byte is shown in hex, never echoed: it may be a control character.
      return absl::InvalidArgumentError(absl::StrFormat(
          "%s has byte 0x%02X at offset %d; ids are printable ASCII without space", field, c, i));
    }
  }
  return absl::OkStatus();
}

absl::StatusOr<std::string> EncodeKey(std::initializer_list<KeyField> fields) {
  std::string key;
  for (const KeyField& field : fields) {
    if (absl::Status status = ValidateId(field.name, field.id); !status.ok()) return status;
    absl::StrAppend(&key, field.id);
    key.push_back(kIdTerminator);
  }
  return key;
}

absl::StatusOr<std::vector<std::string>> DecodeKey(absl::string_view key) {
  std::vector<std::string> ids;
  while (!key.empty()) {
    const size_t end = key.find(kIdTerminator);
    if (end == absl::string_view::npos) {
      return absl::DataLossError(absl::StrCat("stored key has an unterminated id after ",
                                              ids.size(), " ids"));
    }
    const absl::string_view id = key.substr(0, end);
    if (absl::Status status = ValidateId(absl::StrCat("stored key's id ", ids.size()), id);
        !status.ok()) {
      return absl::DataLossError(status.message());
    }
    ids.emplace_back(id);
    key.remove_prefix(end + 1);
  }
  return ids;
}

std::string EncodeVersion(uint64_t version) {
  std::string bytes(8, '\0');
  for (int i = 7; i >= 0; --i) {
    bytes[i] = static_cast<char>(version & 0xFF);
    version >>= 8;
  }
  return bytes;
}

absl::StatusOr<uint64_t> DecodeVersion(absl::string_view bytes) {
  if (bytes.size() != 8) {
    return absl::DataLossError(
        absl::StrCat("stored version is ", bytes.size(), " bytes, not 8"));
  }
  uint64_t version = 0;
  for (char byte : bytes) version = (version << 8) | static_cast<unsigned char>(byte);
  return version;
}

absl::StatusOr<std::string> EncodeClothingBasisKey(const ClothingBasisKey& key) {
  return EncodeKey({{"tenant", key.tenant},
                    {"garment_id", key.garment_id},
                    {"size", key.size},
                    {"avatar_basis_id", key.avatar_basis_id},
                    {"method", key.method}});
}

std::string DescribeClothingBasisKey(const ClothingBasisKey& key) {
  return absl::StrCat("clothing basis (tenant '", key.tenant, "', garment '", key.garment_id,
                      "', size '", key.size, "', avatar basis '", key.avatar_basis_id,
                      "', method '", key.method, "')");
}

}  // namespace fitbase::storage
