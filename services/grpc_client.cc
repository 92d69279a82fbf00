#include "services/grpc_client.h"

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "services/api_key_source.h"
#include "services/call_auth.h"

namespace fitbase::services {
namespace {

constexpr int kMaxMessageBytes = 64 << 20;

}  // namespace

std::string ListenAddress(absl::string_view listen) {
  if (!absl::StrContains(listen, ':')) return absl::StrCat("127.0.0.1:", listen);
  return std::string(listen);
}

void AddRemoteOptions(CLI::App* command, RemoteFlags& flags, const std::string& server_flag) {
  command->add_option(server_flag, flags.address,
                      absl::StrCat("The server's host:port (default ", flags.address, ")"));
  command->add_option("--api-key-file", flags.api_key_file,
                      "File holding the API key (default: $FITBASE_API_KEY)");
  command->add_option("--timeout", flags.timeout_seconds,
                      "Deadline of each call, seconds (default 120)");
}

std::shared_ptr<grpc::Channel> OpenChannel(absl::string_view address) {
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(kMaxMessageBytes);
  arguments.SetMaxSendMessageSize(kMaxMessageBytes);
  return grpc::CreateCustomChannel(ListenAddress(address), grpc::InsecureChannelCredentials(),
                                   arguments);
}

absl::StatusOr<std::unique_ptr<grpc::ClientContext>> NewCallContext(const RemoteFlags& flags,
                                                                    absl::Duration timeout) {
  if (!(flags.timeout_seconds > 0)) return absl::InvalidArgumentError("--timeout must be positive");
  ASSIGN_OR_RETURN(std::string key, flags.api_key_file.empty()
                                        ? ApiKeyFromEnvironment()
                                        : ApiKeyFromFile(flags.api_key_file));
  auto context = std::make_unique<grpc::ClientContext>();
  context->set_deadline(absl::ToChronoTime(absl::Now() + timeout));
  AddApiKey(*context, key);
  return context;
}

absl::Status FromGrpcStatus(const grpc::Status& status) {
  if (status.ok()) return absl::OkStatus();
  return absl::Status(static_cast<absl::StatusCode>(status.error_code()), status.error_message());
}

}  // namespace fitbase::services
