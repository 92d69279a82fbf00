#ifndef FITBASE_SERVICES_RPC_API_KEYS_H_
#define FITBASE_SERVICES_RPC_API_KEYS_H_

#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <string>

#include "absl/container/flat_hash_map.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace fitbase::rpc {

// What a caller of the servers may do. Every key belongs to one tenant and has one role.
enum class Role {
  kCustomer,   // Reads its tenant's catalogue and fits its garments.
  kIngestion,  // Also writes its tenant's catalogue (garments, avatar bases) and builds.
  kAdmin,      // Anything any role may do.
  kWorker,     // Leases and completes drape tasks.
};

// "customer", "ingestion", "admin", "worker"; else INVALID_ARGUMENT listing them.
absl::StatusOr<Role> ParseRole(absl::string_view name);
absl::string_view RoleName(Role role);

// Who made a call, as established by its API key.
struct Principal {
  std::string tenant;
  Role role = Role::kCustomer;
};

// OK when `tenant` is a valid tenant id (storage's id rule, storage/record_key.h); else
// INVALID_ARGUMENT saying what is wrong: services reject at the door what storage would
// reject later.
absl::Status ValidateTenantId(absl::string_view tenant);

// What a key file stores for a key: the lower-case hex SHA-256 of its bytes, so the file
// gives no one the keys and `sha256sum` can provision one by hand.
std::string HashApiKey(absl::string_view key);

// A new secret key: "fb_" and 64 lower-case hex digits (32 bytes from OpenSSL's CSPRNG).
// The prefix lets secret scanners and people recognise a leaked key.
absl::StatusOr<std::string> NewApiKey();

// The API keys a server accepts, loaded at startup from a key file: one key per line,
// `<sha256 hex of the key> <tenant> <role>`; blank lines and lines starting with '#' are
// ignored.
class ApiKeyRegistry {
 public:
  // NOT_FOUND when the file cannot be opened; else as Parse, with the path as name.
  static absl::StatusOr<ApiKeyRegistry> Load(const std::filesystem::path& path);
  // INVALID_ARGUMENT "<name> line <n>: <what>" for the first bad line (wrong field count,
  // bad hash, invalid tenant, unknown role, a hash listed twice). The line itself is never
  // quoted: it may hold a key pasted by mistake where its hash belongs.
  static absl::StatusOr<ApiKeyRegistry> Parse(absl::string_view text, absl::string_view name);

  // The principal of `key`; UNAUTHENTICATED "missing API key" when it is empty, "unknown API
  // key" when no line lists its hash. Errors never contain the key.
  absl::StatusOr<Principal> Authenticate(absl::string_view key) const;

  // Accepts `key` as `principal` too: for keys a process makes for its own parts (the
  // in-process workers of `serve --role all`), never written anywhere.
  void AddKey(absl::string_view key, Principal principal);

  size_t size() const { return by_hash_.size(); }

 private:
  // Keyed by hash, not by key: a lookup's timing can reveal only bits of a hash, from which
  // no key can be recovered.
  absl::flat_hash_map<std::string, Principal> by_hash_;
};

// OK when `principal` is an admin or has one of the `allowed` roles; else PERMISSION_DENIED
// "<role> keys may not <action>", e.g. action "start builds".
absl::Status RequireRole(const Principal& principal, std::initializer_list<Role> allowed,
                         absl::string_view action);

}  // namespace fitbase::rpc

#endif  // FITBASE_SERVICES_RPC_API_KEYS_H_
