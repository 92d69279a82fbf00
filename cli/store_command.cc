// fitbase store checkpoint: a consistent copy of the coordinator's store, made by the
// coordinator (the store's only writer), for backup or a read-only fit service.
#include <iostream>

#include "cli/cli_context.h"
#include "cli/remote_flags.h"
#include "core/status_macros.h"
#include "fitbase/v1/catalog.grpc.pb.h"
#include "services/rpc/channel.h"
#include "services/rpc/grpc_status.h"

namespace fitbase::cli {
namespace {

struct StoreFlags {
  RemoteFlags remote;
  std::string name;
};

absl::Status RunCheckpoint(const StoreFlags& flags) {
  auto stub = v1::Catalog::NewStub(rpc::OpenChannel(flags.remote.address));
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> context,
                   NewCallContext(flags.remote, absl::Seconds(flags.remote.timeout_seconds)));
  v1::CreateCheckpointRequest request;
  request.set_name(flags.name);
  v1::CreateCheckpointResponse response;
  RETURN_IF_ERROR(rpc::FromGrpcStatus(stub->CreateCheckpoint(context.get(), request, &response)));
  std::cout << "checkpoint " << response.path() << "\n";
  return absl::OkStatus();
}

}  // namespace

void AddStoreCommands(CLI::App& app, CliContext& context) {
  CLI::App* store = app.add_subcommand("store", "The coordinator's asset store");
  store->require_subcommand(1);
  auto flags = std::make_shared<StoreFlags>();
  CLI::App* checkpoint = store->add_subcommand(
      "checkpoint", "Copy the store (hard links) beside it, as <db>-checkpoints/NAME (admin key)");
  AddRemoteOptions(checkpoint, flags->remote);
  checkpoint->add_option("--name", flags->name, "Checkpoint name")->required();
  checkpoint->callback(
      [&context, flags] { context.action = [flags] { return RunCheckpoint(*flags); }; });
}

}  // namespace fitbase::cli
