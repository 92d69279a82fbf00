#ifndef FITBASE_SERVICES_BUILD_COORDINATOR_SERVICE_H_
#define FITBASE_SERVICES_BUILD_COORDINATOR_SERVICE_H_

#include <atomic>

#include "absl/status/statusor.h"
#include "fitbase/v1/coordinator.grpc.pb.h"
#include "fitbase/v1/worker_queue.grpc.pb.h"
#include "services/build/coordinator.h"
#include "services/rpc/api_keys.h"

namespace fitbase::build {

// The coordinator the services call, once it has recovered: until then (and after a drain
// begins) calls are UNAVAILABLE, as the health service says NOT_SERVING.
class CoordinatorSlot {
 public:
  void Set(Coordinator* coordinator) { coordinator_.store(coordinator); }
  absl::StatusOr<Coordinator*> Get() const;

 private:
  std::atomic<Coordinator*> coordinator_{nullptr};
};

// fitbase.v1.Coordinator: builds, for ingestion and admin keys; the tenant is the key's.
class CoordinatorService final : public v1::Coordinator::Service {
 public:
  CoordinatorService(const CoordinatorSlot* slot, const rpc::ApiKeyRegistry* keys)
      : slot_(slot), keys_(keys) {}

  grpc::Status SubmitBuild(grpc::ServerContext* context, const v1::SubmitBuildRequest* request,
                           v1::Build* response) override;
  grpc::Status GetBuild(grpc::ServerContext* context, const v1::GetBuildRequest* request,
                        v1::GetBuildResponse* response) override;
  grpc::Status ListBuilds(grpc::ServerContext* context, const v1::ListBuildsRequest* request,
                          v1::ListBuildsResponse* response) override;
  grpc::Status CancelBuild(grpc::ServerContext* context, const v1::CancelBuildRequest* request,
                           v1::Build* response) override;
  grpc::Status WatchBuild(grpc::ServerContext* context, const v1::GetBuildRequest* request,
                          grpc::ServerWriter<v1::Build>* writer) override;

 private:
  // The coordinator and the caller's tenant, or why the call may not proceed.
  absl::StatusOr<std::pair<Coordinator*, std::string>> Admit(const grpc::ServerContext& context,
                                                             absl::string_view action) const;

  const CoordinatorSlot* slot_;
  const rpc::ApiKeyRegistry* keys_;
};

// fitbase.v1.WorkerQueue, for worker and admin keys.
class WorkerQueueService final : public v1::WorkerQueue::Service {
 public:
  WorkerQueueService(const CoordinatorSlot* slot, const rpc::ApiKeyRegistry* keys)
      : slot_(slot), keys_(keys) {}

  grpc::Status LeaseTask(grpc::ServerContext* context, const v1::LeaseTaskRequest* request,
                         v1::LeaseTaskResponse* response) override;
  grpc::Status Heartbeat(grpc::ServerContext* context, const v1::HeartbeatRequest* request,
                         v1::HeartbeatResponse* response) override;
  grpc::Status CompleteTask(grpc::ServerContext* context, const v1::CompleteTaskRequest* request,
                            v1::CompleteTaskResponse* response) override;
  grpc::Status FailTask(grpc::ServerContext* context, const v1::FailTaskRequest* request,
                        v1::FailTaskResponse* response) override;

 private:
  absl::StatusOr<Coordinator*> Admit(const grpc::ServerContext& context) const;

  const CoordinatorSlot* slot_;
  const rpc::ApiKeyRegistry* keys_;
};

}  // namespace fitbase::build

#endif  // FITBASE_SERVICES_BUILD_COORDINATOR_SERVICE_H_
