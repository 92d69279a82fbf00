#ifndef FITBASE_SERVICES_RPC_CALL_AUTH_H_
#define FITBASE_SERVICES_RPC_CALL_AUTH_H_

#include <grpcpp/client_context.h>
#include <grpcpp/server_context.h>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "services/rpc/api_keys.h"

namespace fitbase::rpc {

// The call metadata that carries the caller's API key (gRPC metadata keys are lower case).
inline constexpr char kApiKeyMetadata[] = "x-api-key";

// The principal of the call's API key. UNAUTHENTICATED as ApiKeyRegistry::Authenticate, or
// "several API keys" when the call carries more than one: choosing one would let a proxy's
// key and the client's disagree silently about who is calling. Works for the synchronous,
// callback and generic servers alike (they share ServerContextBase).
absl::StatusOr<Principal> AuthenticateCall(const grpc::ServerContextBase& context,
                                           const ApiKeyRegistry& keys);

// Sends `key` as the call's API key; call it before starting the call.
void AddApiKey(grpc::ClientContext& context, absl::string_view key);

}  // namespace fitbase::rpc

#endif  // FITBASE_SERVICES_RPC_CALL_AUTH_H_
