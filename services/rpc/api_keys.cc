#include "services/rpc/api_keys.h"

#include <openssl/rand.h>

#include <algorithm>
#include <iterator>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/escaping.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "core/content_hash.h"
#include "core/file_util.h"
#include "core/status_macros.h"
#include "core/text_tokens.h"
#include "storage/record_key.h"

namespace fitbase::rpc {
namespace {

// Indexed by Role.
constexpr absl::string_view kRoleNames[] = {"customer", "ingestion", "admin", "worker"};
static_assert(std::size(kRoleNames) == static_cast<size_t>(Role::kWorker) + 1);

constexpr absl::string_view kKeyPrefix = "fb_";
// 256 bits: guessing is hopeless, so keys need no rate limiting or expiry to stay secret.
constexpr int kKeyRandomBytes = 32;
constexpr size_t kHashHexDigits = 64;

// Unlike core::TextLine::Error, does not quote the line (see ApiKeyRegistry::Parse).
absl::Status LineError(const core::TextLine& line, absl::string_view what) {
  return absl::InvalidArgumentError(absl::StrCat(line.label, " line ", line.number, ": ", what));
}

bool IsHexDigest(absl::string_view field) {
  return field.size() == kHashHexDigits && std::ranges::all_of(field, [](char c) {
           return absl::ascii_isxdigit(static_cast<unsigned char>(c));
         });
}

}  // namespace

absl::StatusOr<Role> ParseRole(absl::string_view name) {
  for (size_t i = 0; i < std::size(kRoleNames); ++i) {
    if (kRoleNames[i] == name) return static_cast<Role>(i);
  }
  return absl::InvalidArgumentError(
      absl::StrCat("unknown role '", name, "'; expected one of ", absl::StrJoin(kRoleNames, ", ")));
}

absl::string_view RoleName(Role role) { return kRoleNames[static_cast<size_t>(role)]; }

absl::Status ValidateTenantId(absl::string_view tenant) {
  return storage::ValidateId("tenant", tenant);
}

std::string HashApiKey(absl::string_view key) { return core::Sha256Hex(key); }

absl::StatusOr<std::string> NewApiKey() {
  unsigned char bytes[kKeyRandomBytes];
  if (RAND_bytes(bytes, kKeyRandomBytes) != 1) {
    return absl::InternalError("OpenSSL's RAND_bytes failed; no key was made");
  }
  return absl::StrCat(kKeyPrefix, absl::BytesToHexString(absl::string_view(
                                      reinterpret_cast<const char*>(bytes), sizeof(bytes))));
}

absl::StatusOr<ApiKeyRegistry> ApiKeyRegistry::Load(const std::filesystem::path& path) {
  ASSIGN_OR_RETURN(const std::string text, core::ReadFileToString(path));
  return Parse(text, path.string());
}

absl::StatusOr<ApiKeyRegistry> ApiKeyRegistry::Parse(absl::string_view text,
                                                     absl::string_view name) {
  ApiKeyRegistry registry;
  absl::flat_hash_map<std::string, int> line_of_hash;
  RETURN_IF_ERROR(core::ForEachDataLine(
      text, name, core::CommentStyle::kWholeLine, [&](const core::TextLine& line) -> absl::Status {
        const std::vector<absl::string_view>& fields = *line.tokens;
        if (fields.size() != 3) {
          return LineError(line, absl::StrCat("expected '<sha256 hex> <tenant> <role>', got ",
                                              fields.size(), " fields"));
        }
        if (!IsHexDigest(fields[0])) {
          return LineError(line, "the first field is not a SHA-256 in 64 hex digits");
        }
        if (absl::Status status = ValidateTenantId(fields[1]); !status.ok()) {
          return LineError(line, status.message());
        }
        absl::StatusOr<Role> role = ParseRole(fields[2]);
        if (!role.ok()) return LineError(line, role.status().message());
        std::string hash = absl::AsciiStrToLower(fields[0]);
        if (auto [it, inserted] = line_of_hash.try_emplace(hash, line.number); !inserted) {
          return LineError(line, absl::StrCat("the key's hash is already on line ", it->second));
        }
        registry.by_hash_.try_emplace(std::move(hash), Principal{std::string(fields[1]), *role});
        return absl::OkStatus();
      }));
  return registry;
}

void ApiKeyRegistry::AddKey(absl::string_view key, Principal principal) {
  by_hash_.insert_or_assign(HashApiKey(key), std::move(principal));
}

absl::StatusOr<Principal> ApiKeyRegistry::Authenticate(absl::string_view key) const {
  if (key.empty()) return absl::UnauthenticatedError("missing API key");
  const auto it = by_hash_.find(HashApiKey(key));
  if (it == by_hash_.end()) return absl::UnauthenticatedError("unknown API key");
  return it->second;
}

absl::Status RequireRole(const Principal& principal, std::initializer_list<Role> allowed,
                         absl::string_view action) {
  if (principal.role == Role::kAdmin ||
      std::ranges::find(allowed, principal.role) != allowed.end()) {
    return absl::OkStatus();
  }
  return absl::PermissionDeniedError(
      absl::StrCat(RoleName(principal.role), " keys may not ", action));
}

}  // namespace fitbase::rpc
