#ifndef FITBASE_SERVICES_GRPC_CLIENT_H_
#define FITBASE_SERVICES_GRPC_CLIENT_H_

#include <memory>
#include <string>

#include "CLI/CLI.hpp"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "grpcpp/grpcpp.h"

namespace fitbase::services {

// How the CLI's client commands reach a server: --coordinator, --api-key-file (default
// $FITBASE_API_KEY) and --timeout, the deadline of each call.
struct RemoteFlags {
  std::string address = "127.0.0.1:7401";
  std::string api_key_file;
  double timeout_seconds = 120;
};

// `server_flag` names the address option ("--coordinator", or "--server" for the fit service).
void AddRemoteOptions(CLI::App* command, RemoteFlags& flags,
                      const std::string& server_flag = "--coordinator");

// A host:port; "PORT" alone means 127.0.0.1:PORT.
std::string ListenAddress(absl::string_view listen);

// A channel with the message size limits of the servers.
std::shared_ptr<grpc::Channel> OpenChannel(absl::string_view address);

// A context with the caller's key and a deadline `timeout` from now.
absl::StatusOr<std::unique_ptr<grpc::ClientContext>> NewCallContext(const RemoteFlags& flags,
                                                                    absl::Duration timeout);

absl::Status FromGrpcStatus(const grpc::Status& status);

}  // namespace fitbase::services

#endif  // FITBASE_SERVICES_GRPC_CLIENT_H_
