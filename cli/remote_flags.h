#ifndef FITBASE_CLI_REMOTE_FLAGS_H_
#define FITBASE_CLI_REMOTE_FLAGS_H_

#include <memory>
#include <string>

#include "CLI/CLI.hpp"
#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "grpcpp/grpcpp.h"

namespace fitbase::cli {

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

// A context with the caller's key and a deadline `timeout` from now.
absl::StatusOr<std::unique_ptr<grpc::ClientContext>> NewCallContext(const RemoteFlags& flags,
                                                                    absl::Duration timeout);

}  // namespace fitbase::cli

#endif  // FITBASE_CLI_REMOTE_FLAGS_H_
