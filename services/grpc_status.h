#ifndef FITBASE_SERVICES_GRPC_STATUS_H_
#define FITBASE_SERVICES_GRPC_STATUS_H_

#include "absl/status/status.h"
#include "grpcpp/support/status.h"

namespace fitbase::services {

// The one place absl statuses become gRPC statuses: the canonical codes are the same numbers.
inline grpc::Status ToGrpcStatus(const absl::Status& status) {
  if (status.ok()) return grpc::Status::OK;
  return grpc::Status(static_cast<grpc::StatusCode>(status.code()),
                      std::string(status.message()));
}

}  // namespace fitbase::services

#endif  // FITBASE_SERVICES_GRPC_STATUS_H_
