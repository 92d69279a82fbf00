#ifndef FITBASE_SERVICES_RPC_GRPC_STATUS_H_
#define FITBASE_SERVICES_RPC_GRPC_STATUS_H_

#include "absl/status/status.h"
#include "grpcpp/support/status.h"

namespace fitbase::rpc {

// The one place absl statuses become gRPC statuses: the canonical codes are the same numbers.
inline grpc::Status ToGrpcStatus(const absl::Status& status) {
  if (status.ok()) return grpc::Status::OK;
  return grpc::Status(static_cast<grpc::StatusCode>(status.code()),
                      std::string(status.message()));
}

// And back, where a client reads a server's answer.
inline absl::Status FromGrpcStatus(const grpc::Status& status) {
  if (status.ok()) return absl::OkStatus();
  return absl::Status(static_cast<absl::StatusCode>(status.error_code()), status.error_message());
}

}  // namespace fitbase::rpc

#endif  // FITBASE_SERVICES_RPC_GRPC_STATUS_H_
