#ifndef FITBASE_SERVICES_RPC_RPC_CHANNEL_H_
#define FITBASE_SERVICES_RPC_RPC_CHANNEL_H_

#include <memory>
#include <string>

#include "absl/strings/string_view.h"
#include "grpcpp/grpcpp.h"

namespace fitbase::rpc {

// The largest message our servers and clients send or accept: clothing bases of large garments
// run past gRPC's 4 MB default.
inline constexpr int kMaxMessageBytes = 64 << 20;

// A host:port; "PORT" alone means 127.0.0.1:PORT.
std::string ListenAddress(absl::string_view listen);

// A channel with the message size limits of the servers.
std::shared_ptr<grpc::Channel> OpenChannel(absl::string_view address);

}  // namespace fitbase::rpc

#endif  // FITBASE_SERVICES_RPC_RPC_CHANNEL_H_
