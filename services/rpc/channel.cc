#include "services/rpc/channel.h"

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"

namespace fitbase::rpc {

std::string ListenAddress(absl::string_view listen) {
  if (!absl::StrContains(listen, ':')) return absl::StrCat("127.0.0.1:", listen);
  return std::string(listen);
}

std::shared_ptr<grpc::Channel> OpenChannel(absl::string_view address) {
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(kMaxMessageBytes);
  arguments.SetMaxSendMessageSize(kMaxMessageBytes);
  return grpc::CreateCustomChannel(ListenAddress(address), grpc::InsecureChannelCredentials(),
                                   arguments);
}

}  // namespace fitbase::rpc
