#include "cli/remote_flags.h"

#include "absl/strings/str_cat.h"
#include "cli/api_key_source.h"
#include "core/status_macros.h"
#include "services/rpc/call_auth.h"

namespace fitbase::cli {

void AddRemoteOptions(CLI::App* command, RemoteFlags& flags, const std::string& server_flag) {
  command->add_option(server_flag, flags.address,
                      absl::StrCat("The server's host:port (default ", flags.address, ")"));
  command->add_option("--api-key-file", flags.api_key_file,
                      "File holding the API key (default: $FITBASE_API_KEY)");
  command->add_option("--timeout", flags.timeout_seconds,
                      "Deadline of each call, seconds (default 120)");
}

absl::StatusOr<std::unique_ptr<grpc::ClientContext>> NewCallContext(const RemoteFlags& flags,
                                                                    absl::Duration timeout) {
  if (!(flags.timeout_seconds > 0)) return absl::InvalidArgumentError("--timeout must be positive");
  ASSIGN_OR_RETURN(std::string key, flags.api_key_file.empty()
                                        ? ApiKeyFromEnvironment()
                                        : ApiKeyFromFile(flags.api_key_file));
  auto context = std::make_unique<grpc::ClientContext>();
  context->set_deadline(absl::ToChronoTime(absl::Now() + timeout));
  rpc::AddApiKey(*context, key);
  return context;
}

}  // namespace fitbase::cli
