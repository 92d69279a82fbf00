#include "services/rpc/api_keys.h"

#include <fstream>
#include <set>
#include <string>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::rpc {
namespace {

using ::fitbase::core::StatusIs;
using ::testing::HasSubstr;
using ::testing::Not;

constexpr absl::string_view kCustomerKey = "fb_customer-key";
constexpr absl::string_view kWorkerKey = "fb_worker-key";

std::string KeyLine(absl::string_view key, absl::string_view tenant, absl::string_view role) {
  return absl::StrCat(HashApiKey(key), " ", tenant, " ", role, "\n");
}

TEST(ApiKeysTest, HashIsPlainSha256Hex) {
  EXPECT_EQ(HashApiKey("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(ApiKeysTest, RoleNamesRoundTrip) {
  for (Role role : {Role::kCustomer, Role::kIngestion, Role::kAdmin, Role::kWorker}) {
    absl::StatusOr<Role> parsed = ParseRole(RoleName(role));
    ASSERT_TRUE(parsed.ok()) << parsed.status();
    EXPECT_EQ(*parsed, role);
  }
  EXPECT_EQ(RoleName(Role::kIngestion), "ingestion");
  EXPECT_THAT(ParseRole("Admin"),
              StatusIs(absl::StatusCode::kInvalidArgument, "customer, ingestion, admin, worker"));
}

TEST(ApiKeysTest, NewKeysAreDistinctPrefixedHex) {
  std::set<std::string> keys;
  for (int i = 0; i < 16; ++i) {
    absl::StatusOr<std::string> key = NewApiKey();
    ASSERT_TRUE(key.ok()) << key.status();
    ASSERT_EQ(key->size(), 67u);
    EXPECT_EQ(key->substr(0, 3), "fb_");
    for (char c : key->substr(3)) {
      EXPECT_TRUE(absl::ascii_isdigit(c) || (c >= 'a' && c <= 'f')) << *key;
    }
    keys.insert(*key);
  }
  EXPECT_EQ(keys.size(), 16u);
}

TEST(ApiKeysTest, AuthenticatesListedKeys) {
  const std::string text =
      absl::StrCat("# fitbase API keys\n\n", KeyLine(kCustomerKey, "acme", "customer"), "  ",
                   KeyLine(kWorkerKey, "ops", "worker"));
  absl::StatusOr<ApiKeyRegistry> keys = ApiKeyRegistry::Parse(text, "keys.txt");
  ASSERT_TRUE(keys.ok()) << keys.status();
  EXPECT_EQ(keys->size(), 2u);

  absl::StatusOr<Principal> customer = keys->Authenticate(kCustomerKey);
  ASSERT_TRUE(customer.ok()) << customer.status();
  EXPECT_EQ(customer->tenant, "acme");
  EXPECT_EQ(customer->role, Role::kCustomer);
  absl::StatusOr<Principal> worker = keys->Authenticate(kWorkerKey);
  ASSERT_TRUE(worker.ok()) << worker.status();
  EXPECT_EQ(worker->tenant, "ops");
  EXPECT_EQ(worker->role, Role::kWorker);
}

TEST(ApiKeysTest, AcceptsUpperCaseHashes) {
  const std::string text =
      absl::StrCat(absl::AsciiStrToUpper(HashApiKey(kCustomerKey)), " acme ingestion\n");
  absl::StatusOr<ApiKeyRegistry> keys = ApiKeyRegistry::Parse(text, "keys.txt");
  ASSERT_TRUE(keys.ok()) << keys.status();
  absl::StatusOr<Principal> principal = keys->Authenticate(kCustomerKey);
  ASSERT_TRUE(principal.ok()) << principal.status();
  EXPECT_EQ(principal->role, Role::kIngestion);
}

TEST(ApiKeysTest, RejectsUnknownAndMissingKeysWithoutEchoingThem) {
  absl::StatusOr<ApiKeyRegistry> keys =
      ApiKeyRegistry::Parse(KeyLine(kCustomerKey, "acme", "customer"), "keys.txt");
  ASSERT_TRUE(keys.ok()) << keys.status();
  const std::string wrong = "fb_not-a-listed-key";
  absl::StatusOr<Principal> principal = keys->Authenticate(wrong);
  EXPECT_THAT(principal, StatusIs(absl::StatusCode::kUnauthenticated, "unknown API key"));
  EXPECT_THAT(std::string(principal.status().message()), Not(HasSubstr(wrong)));
  // A key's hash is not a key.
  EXPECT_THAT(keys->Authenticate(HashApiKey(kCustomerKey)),
              StatusIs(absl::StatusCode::kUnauthenticated, "unknown API key"));
  EXPECT_THAT(keys->Authenticate(""),
              StatusIs(absl::StatusCode::kUnauthenticated, "missing API key"));
}

TEST(ApiKeysTest, BadLinesNameFileAndLine) {
  const std::string good = KeyLine(kCustomerKey, "acme", "customer");
  const std::string hash = HashApiKey(kWorkerKey);
  struct Case {
    std::string bad_line;
    std::string error;
  };
  const Case cases[] = {
      {absl::StrCat(hash, " acme\n"), "expected '<sha256 hex> <tenant> <role>', got 2 fields"},
      {absl::StrCat(hash, " acme customer extra\n"),
       "expected '<sha256 hex> <tenant> <role>', got 4 fields"},
      {absl::StrCat(hash.substr(1), " acme customer\n"),
       "the first field is not a SHA-256 in 64 hex digits"},
      {absl::StrCat("g", hash.substr(1), " acme customer\n"),
       "the first field is not a SHA-256 in 64 hex digits"},
      {absl::StrCat(hash, " acme owner\n"), "unknown role 'owner'"},
      {absl::StrCat(hash, " ac\x01me customer\n"), "tenant has byte 0x01 at offset 2"},
      {absl::StrCat(hash, " ", std::string(257, 't'), " customer\n"),
       "tenant is 257 bytes, more than 256"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.bad_line);
    EXPECT_THAT(
        ApiKeyRegistry::Parse(absl::StrCat("# keys\n", good, c.bad_line), "keys.txt"),
        StatusIs(absl::StatusCode::kInvalidArgument, absl::StrCat("keys.txt line 3: ", c.error)));
  }
}

TEST(ApiKeysTest, ErrorsNeverQuoteTheLine) {
  // The usual mistake: the key itself pasted where its hash belongs.
  const std::string key = absl::StrCat("fb_", std::string(64, 'a'));
  absl::StatusOr<ApiKeyRegistry> keys =
      ApiKeyRegistry::Parse(absl::StrCat(key, " acme customer\n"), "keys.txt");
  EXPECT_THAT(keys, StatusIs(absl::StatusCode::kInvalidArgument, "keys.txt line 1: "));
  EXPECT_THAT(std::string(keys.status().message()), Not(HasSubstr("aaaaaaaa")));
}

TEST(ApiKeysTest, RejectsAHashListedTwice) {
  const std::string text =
      absl::StrCat(KeyLine(kCustomerKey, "acme", "customer"), KeyLine(kWorkerKey, "ops", "worker"),
                   "\n", absl::AsciiStrToUpper(HashApiKey(kCustomerKey)), " other admin\n");
  EXPECT_THAT(ApiKeyRegistry::Parse(text, "keys.txt"),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       "keys.txt line 4: the key's hash is already on line 1"));
}

TEST(ApiKeysTest, LoadsFilesAndNamesMissingOnes) {
  const std::filesystem::path path = core::ProcessTempDir() / "keys.txt";
  std::ofstream(path) << KeyLine(kCustomerKey, "acme", "customer") << "not a line\n";
  EXPECT_THAT(ApiKeyRegistry::Load(path),
              StatusIs(absl::StatusCode::kInvalidArgument, absl::StrCat(path.string(), " line 2")));
  std::ofstream(path) << KeyLine(kCustomerKey, "acme", "customer");
  absl::StatusOr<ApiKeyRegistry> keys = ApiKeyRegistry::Load(path);
  ASSERT_TRUE(keys.ok()) << keys.status();
  EXPECT_EQ(keys->size(), 1u);
  EXPECT_THAT(ApiKeyRegistry::Load(core::ProcessTempDir() / "absent.txt"),
              StatusIs(absl::StatusCode::kNotFound, "absent.txt"));
}

TEST(ApiKeysTest, TenantIdsFollowTheStorageIdRule) {
  EXPECT_TRUE(ValidateTenantId("acme-EU_1.shop~").ok());
  EXPECT_TRUE(ValidateTenantId(std::string(256, '!')).ok());
  EXPECT_THAT(ValidateTenantId(""), StatusIs(absl::StatusCode::kInvalidArgument, "empty"));
  EXPECT_THAT(ValidateTenantId("a b"),
              StatusIs(absl::StatusCode::kInvalidArgument, "byte 0x20 at offset 1"));
  EXPECT_THAT(ValidateTenantId("\x7F"), StatusIs(absl::StatusCode::kInvalidArgument, "0x7F"));
}

TEST(ApiKeysTest, RequireRoleAdmitsTheAllowedRolesAndAdmins) {
  const Role roles[] = {Role::kCustomer, Role::kIngestion, Role::kAdmin, Role::kWorker};
  for (Role role : roles) {
    const Principal principal{"acme", role};
    SCOPED_TRACE(RoleName(role));
    EXPECT_EQ(RequireRole(principal, {Role::kIngestion}, "write the catalogue").ok(),
              role == Role::kIngestion || role == Role::kAdmin);
    EXPECT_EQ(RequireRole(principal, {Role::kCustomer, Role::kIngestion}, "fit").ok(),
              role != Role::kWorker);
    EXPECT_EQ(RequireRole(principal, {}, "manage keys").ok(), role == Role::kAdmin);
  }
  EXPECT_THAT(RequireRole(Principal{"acme", Role::kCustomer}, {Role::kWorker}, "lease tasks"),
              StatusIs(absl::StatusCode::kPermissionDenied, "customer keys may not lease tasks"));
}

}  // namespace
}  // namespace fitbase::rpc
