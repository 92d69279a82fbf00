#ifndef FITBASE_SERVICES_RPC_TLS_CREDENTIALS_H_
#define FITBASE_SERVICES_RPC_TLS_CREDENTIALS_H_

#include <filesystem>
#include <memory>

#include "absl/status/statusor.h"
#include "grpcpp/security/credentials.h"
#include "grpcpp/security/server_credentials.h"

namespace fitbase::rpc {

// PEM files of one side of a TLS connection.
struct TlsFiles {
  std::filesystem::path cert;  // This side's certificate chain.
  std::filesystem::path key;   // Its private key.
  std::filesystem::path ca;    // The CA that signs the other side's certificates.
};

// A server's credentials: `cert` and `key` required; with `ca`, every client must present a
// certificate signed by it (mutual TLS: only the cluster's workers connect). NOT_FOUND naming
// a missing file, INVALID_ARGUMENT for a missing cert or key.
absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> TlsServerCredentials(
    const TlsFiles& files);

// A client's credentials: `ca` verifies the server (empty: the system's roots); `cert` and
// `key`, if given, prove the client to a server that asks.
absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> TlsChannelCredentials(
    const TlsFiles& files);

}  // namespace fitbase::rpc

#endif  // FITBASE_SERVICES_RPC_TLS_CREDENTIALS_H_
