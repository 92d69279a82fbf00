#include "services/build/coordinator_service.h"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "core/status_macros.h"
#include "services/rpc/call_auth.h"
#include "services/rpc/grpc_status.h"

namespace fitbase::build {
namespace {

// Long-polls answer at least this often, so a client learns of a lost server.
constexpr absl::Duration kMaxWait = absl::Seconds(30);
// A watch wakes at least this often to notice that its client went away.
constexpr absl::Duration kWatchPoll = absl::Seconds(1);
// Answered this long before the caller's deadline, so an empty answer arrives in time.
constexpr absl::Duration kDeadlineMargin = absl::Milliseconds(200);

absl::Time WaitDeadline(const grpc::ServerContext& context, absl::Duration wanted) {
  const absl::Time call_deadline = absl::FromChrono(context.deadline()) - kDeadlineMargin;
  return std::min({absl::Now() + std::min(wanted, kMaxWait), call_deadline});
}

}  // namespace

absl::StatusOr<Coordinator*> CoordinatorSlot::Get() const {
  Coordinator* coordinator = coordinator_.load();
  if (coordinator == nullptr) {
    return absl::UnavailableError("the coordinator is recovering or draining; retry");
  }
  return coordinator;
}

absl::StatusOr<std::pair<Coordinator*, std::string>> CoordinatorService::Admit(
    const grpc::ServerContext& context, absl::string_view action) const {
  ASSIGN_OR_RETURN(rpc::Principal principal, rpc::AuthenticateCall(context, *keys_));
  RETURN_IF_ERROR(rpc::RequireRole(principal, {rpc::Role::kIngestion}, action));
  ASSIGN_OR_RETURN(Coordinator * coordinator, slot_->Get());
  return std::make_pair(coordinator, principal.tenant);
}

grpc::Status CoordinatorService::SubmitBuild(grpc::ServerContext* context,
                                             const v1::SubmitBuildRequest* request,
                                             v1::Build* response) {
  auto admitted = Admit(*context, "start builds");
  if (!admitted.ok()) return rpc::ToGrpcStatus(admitted.status());
  auto [coordinator, tenant] = *admitted;
  absl::StatusOr<v1::Build> build = coordinator->Submit(tenant, request->request());
  if (!build.ok()) return rpc::ToGrpcStatus(build.status());
  *response = *std::move(build);
  return grpc::Status::OK;
}

grpc::Status CoordinatorService::GetBuild(grpc::ServerContext* context,
                                          const v1::GetBuildRequest* request,
                                          v1::GetBuildResponse* response) {
  auto admitted = Admit(*context, "read builds");
  if (!admitted.ok()) return rpc::ToGrpcStatus(admitted.status());
  auto [coordinator, tenant] = *admitted;
  absl::StatusOr<BuildSnapshot> snapshot =
      coordinator->GetBuild(tenant, request->build_id(), request->with_tasks());
  if (!snapshot.ok()) return rpc::ToGrpcStatus(snapshot.status());
  *response->mutable_build() = std::move(snapshot->build);
  for (v1::Task& task : snapshot->tasks) *response->add_tasks() = std::move(task);
  return grpc::Status::OK;
}

grpc::Status CoordinatorService::ListBuilds(grpc::ServerContext* context,
                                            const v1::ListBuildsRequest*,
                                            v1::ListBuildsResponse* response) {
  auto admitted = Admit(*context, "read builds");
  if (!admitted.ok()) return rpc::ToGrpcStatus(admitted.status());
  auto [coordinator, tenant] = *admitted;
  for (v1::Build& build : coordinator->ListBuilds(tenant)) {
    *response->add_builds() = std::move(build);
  }
  return grpc::Status::OK;
}

grpc::Status CoordinatorService::CancelBuild(grpc::ServerContext* context,
                                             const v1::CancelBuildRequest* request,
                                             v1::Build* response) {
  auto admitted = Admit(*context, "cancel builds");
  if (!admitted.ok()) return rpc::ToGrpcStatus(admitted.status());
  auto [coordinator, tenant] = *admitted;
  absl::StatusOr<v1::Build> build = coordinator->Cancel(tenant, request->build_id());
  if (!build.ok()) return rpc::ToGrpcStatus(build.status());
  *response = *std::move(build);
  return grpc::Status::OK;
}

grpc::Status CoordinatorService::WatchBuild(grpc::ServerContext* context,
                                            const v1::GetBuildRequest* request,
                                            grpc::ServerWriter<v1::Build>* writer) {
  auto admitted = Admit(*context, "read builds");
  if (!admitted.ok()) return rpc::ToGrpcStatus(admitted.status());
  auto [coordinator, tenant] = *admitted;
  uint64_t seen = 0;
  bool first = true;
  while (!context->IsCancelled()) {
    absl::StatusOr<BuildSnapshot> snapshot = coordinator->WaitForBuild(
        tenant, request->build_id(), seen, WaitDeadline(*context, kWatchPoll));
    if (!snapshot.ok()) return rpc::ToGrpcStatus(snapshot.status());
    if (first || snapshot->revision > seen) {
      if (!writer->Write(snapshot->build)) return grpc::Status::CANCELLED;
      first = false;
      seen = snapshot->revision;
    }
    const v1::BuildPhase phase = snapshot->build.phase();
    if (phase == v1::BUILD_SUCCEEDED || phase == v1::BUILD_FAILED ||
        phase == v1::BUILD_CANCELLED) {
      return grpc::Status::OK;
    }
    if (absl::Now() >= absl::FromChrono(context->deadline()) - kDeadlineMargin) {
      return grpc::Status(grpc::StatusCode::DEADLINE_EXCEEDED, "the watch's deadline passed");
    }
  }
  return grpc::Status::CANCELLED;
}

absl::StatusOr<Coordinator*> WorkerQueueService::Admit(const grpc::ServerContext& context) const {
  ASSIGN_OR_RETURN(rpc::Principal principal, rpc::AuthenticateCall(context, *keys_));
  RETURN_IF_ERROR(rpc::RequireRole(principal, {rpc::Role::kWorker}, "run drape tasks"));
  return slot_->Get();
}

grpc::Status WorkerQueueService::LeaseTask(grpc::ServerContext* context,
                                           const v1::LeaseTaskRequest* request,
                                           v1::LeaseTaskResponse* response) {
  absl::StatusOr<Coordinator*> coordinator = Admit(*context);
  if (!coordinator.ok()) return rpc::ToGrpcStatus(coordinator.status());
  if (request->worker().empty() || request->worker().size() > 256) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "worker must be 1 to 256 bytes");
  }
  absl::StatusOr<std::optional<LeasedTask>> leased = (*coordinator)->Lease(
      request->worker(), WaitDeadline(*context, absl::Milliseconds(request->wait_ms())));
  if (!leased.ok()) return rpc::ToGrpcStatus(leased.status());
  if (leased->has_value()) {
    *response->mutable_lease() = std::move((*leased)->lease);
    *response->mutable_spec() = std::move((*leased)->spec);
  }
  return grpc::Status::OK;
}

grpc::Status WorkerQueueService::Heartbeat(grpc::ServerContext* context,
                                           const v1::HeartbeatRequest* request,
                                           v1::HeartbeatResponse* response) {
  absl::StatusOr<Coordinator*> coordinator = Admit(*context);
  if (!coordinator.ok()) return rpc::ToGrpcStatus(coordinator.status());
  absl::StatusOr<absl::Time> expiry = (*coordinator)->Heartbeat(request->key(), request->token());
  if (!expiry.ok()) return rpc::ToGrpcStatus(expiry.status());
  response->set_expiry_unix_ms(absl::ToUnixMillis(*expiry));
  return grpc::Status::OK;
}

grpc::Status WorkerQueueService::CompleteTask(grpc::ServerContext* context,
                                              const v1::CompleteTaskRequest* request,
                                              v1::CompleteTaskResponse*) {
  absl::StatusOr<Coordinator*> coordinator = Admit(*context);
  if (!coordinator.ok()) return rpc::ToGrpcStatus(coordinator.status());
  return rpc::ToGrpcStatus(
      (*coordinator)->Complete(request->key(), request->token(), request->result()));
}

grpc::Status WorkerQueueService::FailTask(grpc::ServerContext* context,
                                          const v1::FailTaskRequest* request,
                                          v1::FailTaskResponse*) {
  absl::StatusOr<Coordinator*> coordinator = Admit(*context);
  if (!coordinator.ok()) return rpc::ToGrpcStatus(coordinator.status());
  // Bounded: the error lands in logs and build records.
  const std::string error = request->error().substr(0, 4096);
  return rpc::ToGrpcStatus(
      (*coordinator)->Fail(request->key(), request->token(), error, request->returned()));
}

}  // namespace fitbase::build
