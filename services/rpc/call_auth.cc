#include "services/rpc/call_auth.h"

#include <iterator>
#include <string>

#include "absl/status/status.h"

namespace fitbase::rpc {

absl::StatusOr<Principal> AuthenticateCall(const grpc::ServerContextBase& context,
                                           const ApiKeyRegistry& keys) {
  const auto [first, last] = context.client_metadata().equal_range(kApiKeyMetadata);
  if (first == last) return keys.Authenticate(absl::string_view());
  if (std::next(first) != last) return absl::UnauthenticatedError("several API keys");
  return keys.Authenticate(absl::string_view(first->second.data(), first->second.size()));
}

void AddApiKey(grpc::ClientContext& context, absl::string_view key) {
  context.AddMetadata(kApiKeyMetadata, std::string(key));
}

}  // namespace fitbase::rpc
