// fitbase build submit|status|watch|cancel|list: the coordinator's builds, from the shell.
#include <iostream>

#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "cli/cli_context.h"
#include "cli/remote_flags.h"
#include "core/status_macros.h"
#include "fitbase/v1/coordinator.grpc.pb.h"
#include "pipeline/progress_reporter.h"
#include "proto/json_codec.h"
#include "services/rpc/channel.h"
#include "services/rpc/grpc_status.h"

namespace fitbase::cli {
namespace {

struct BuildFlags {
  RemoteFlags remote;
  std::string garment;
  std::string sizes = "M";
  std::string methods = "linear";
  std::string basis_id;
  double scale = 0;
  uint32_t samples = 0;
  uint64_t sample_seed = 0;
  workers::DrapeSchedule schedule;
  bool watch = false;
  double watch_seconds = 24 * 3600;
  std::string build_id;
  bool tasks = false;
};

std::string Summary(const v1::Build& build) {
  std::string text = absl::StrFormat(
      "%s %s: garment %s sizes %s methods %s, %d/%d tasks done (%d cache hits)",
      build.build_id(), v1::BuildPhase_Name(build.phase()), build.request().garment_id(),
      absl::StrJoin(build.request().sizes(), ","), absl::StrJoin(build.request().methods(), ","),
      build.tasks_done(), build.tasks_total(), build.cache_hits());
  if (!build.error().empty()) absl::StrAppend(&text, "\n  error: ", build.error());
  for (const v1::PublishedClothingBasis& p : build.published()) {
    absl::StrAppend(&text, absl::StrFormat("\n  published %s %s: clothing basis %s version %d",
                                           p.size(), p.method(), p.clothing_basis_id(),
                                           p.version()));
  }
  return text;
}

// Follows the build to its end, with a progress line; FAILED_PRECONDITION unless it succeeds.
absl::Status Watch(v1::Coordinator::Stub& stub, const BuildFlags& flags,
                   const std::string& build_id) {
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> context,
                   NewCallContext(flags.remote, absl::Seconds(flags.watch_seconds)));
  v1::GetBuildRequest request;
  request.set_build_id(build_id);
  std::unique_ptr<grpc::ClientReader<v1::Build>> reader = stub.WatchBuild(context.get(), request);
  v1::Build build;
  std::unique_ptr<pipeline::ProgressReporter> progress;
  while (reader->Read(&build)) {
    if (progress == nullptr) {
      progress = std::make_unique<pipeline::ProgressReporter>(absl::StrCat(build_id, " drapes"),
                                                    build.tasks_total(), std::cerr,
                                                    pipeline::StderrIsTerminal());
      progress->Resume(build.tasks_done());
    }
    progress->Update(build.tasks_done());
  }
  RETURN_IF_ERROR(rpc::FromGrpcStatus(reader->Finish()));
  if (progress != nullptr) progress->Finish();
  std::cout << Summary(build) << "\n";
  if (build.phase() != v1::BUILD_SUCCEEDED) {
    return absl::FailedPreconditionError(
        absl::StrCat("build ", build_id, " ended ", v1::BuildPhase_Name(build.phase())));
  }
  return absl::OkStatus();
}

absl::Status RunSubmit(const BuildFlags& flags) {
  auto stub = v1::Coordinator::NewStub(rpc::OpenChannel(flags.remote.address));
  v1::SubmitBuildRequest request;
  v1::BuildRequest& build = *request.mutable_request();
  build.set_garment_id(flags.garment);
  for (absl::string_view size : absl::StrSplit(flags.sizes, ',', absl::SkipWhitespace())) {
    build.add_sizes(std::string(size));
  }
  for (absl::string_view method : absl::StrSplit(flags.methods, ',', absl::SkipWhitespace())) {
    build.add_methods(std::string(method));
  }
  build.set_avatar_basis_id(flags.basis_id);
  build.set_example_scale(flags.scale);
  build.set_sampled_drapes(flags.samples);
  build.set_sample_seed(flags.sample_seed);
  build.set_homotopy_steps(static_cast<uint32_t>(flags.schedule.homotopy_steps));
  build.set_relax_steps(static_cast<uint32_t>(flags.schedule.relax_steps));
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> context,
                   NewCallContext(flags.remote, absl::Seconds(flags.remote.timeout_seconds)));
  v1::Build submitted;
  RETURN_IF_ERROR(rpc::FromGrpcStatus(stub->SubmitBuild(context.get(), request, &submitted)));
  std::cout << Summary(submitted) << "\n";
  if (!flags.watch) return absl::OkStatus();
  return Watch(*stub, flags, submitted.build_id());
}

absl::Status RunStatus(const BuildFlags& flags) {
  auto stub = v1::Coordinator::NewStub(rpc::OpenChannel(flags.remote.address));
  v1::GetBuildRequest request;
  request.set_build_id(flags.build_id);
  request.set_with_tasks(flags.tasks);
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> context,
                   NewCallContext(flags.remote, absl::Seconds(flags.remote.timeout_seconds)));
  v1::GetBuildResponse response;
  RETURN_IF_ERROR(rpc::FromGrpcStatus(stub->GetBuild(context.get(), request, &response)));
  if (flags.tasks) {
    std::cout << proto::ToJson(response) << "\n";
  } else {
    std::cout << Summary(response.build()) << "\n";
  }
  return absl::OkStatus();
}

absl::Status RunCancel(const BuildFlags& flags) {
  auto stub = v1::Coordinator::NewStub(rpc::OpenChannel(flags.remote.address));
  v1::CancelBuildRequest request;
  request.set_build_id(flags.build_id);
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> context,
                   NewCallContext(flags.remote, absl::Seconds(flags.remote.timeout_seconds)));
  v1::Build build;
  RETURN_IF_ERROR(rpc::FromGrpcStatus(stub->CancelBuild(context.get(), request, &build)));
  std::cout << Summary(build) << "\n";
  return absl::OkStatus();
}

absl::Status RunList(const BuildFlags& flags) {
  auto stub = v1::Coordinator::NewStub(rpc::OpenChannel(flags.remote.address));
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> context,
                   NewCallContext(flags.remote, absl::Seconds(flags.remote.timeout_seconds)));
  v1::ListBuildsResponse response;
  RETURN_IF_ERROR(rpc::FromGrpcStatus(stub->ListBuilds(context.get(), {}, &response)));
  for (const v1::Build& build : response.builds()) std::cout << Summary(build) << "\n";
  return absl::OkStatus();
}

}  // namespace

void AddBuildCommands(CLI::App& app, CliContext& context) {
  CLI::App* build = app.add_subcommand("build", "Clothing-basis builds on the coordinator");
  build->require_subcommand(1);
  auto flags = std::make_shared<BuildFlags>();

  CLI::App* submit = build->add_subcommand("submit", "Start a build of a garment's sizes");
  AddRemoteOptions(submit, flags->remote);
  submit->add_option("--garment", flags->garment, "Garment id (from `catalog upload`)")
      ->required();
  submit->add_option("--sizes", flags->sizes, "Comma-separated sizes (default M)");
  submit->add_option("--methods", flags->methods,
                     "Comma-separated: paper, linear, quadratic, kernel (default linear)");
  submit->add_option("--samples", flags->samples,
                     "Bodies sampled from the population and draped per size, for kernel");
  submit->add_option("--sample-seed", flags->sample_seed, "Seed of the sampled bodies (default 1)");
  submit->add_option("--basis-id", flags->basis_id,
                     "Avatar basis id (default: the one the garment was imported on)");
  submit->add_option("--scale", flags->scale, "Example scale s (default 1)");
  AddDrapeScheduleOptions(submit, flags->schedule);
  submit->add_flag("--watch", flags->watch, "Follow the build to its end with a progress bar");
  submit->callback([&context, flags] { context.action = [flags] { return RunSubmit(*flags); }; });

  CLI::App* status = build->add_subcommand("status", "A build's state");
  AddRemoteOptions(status, flags->remote);
  status->add_option("build_id", flags->build_id, "Build id")->required();
  status->add_flag("--tasks", flags->tasks, "Print the build and its tasks as JSON");
  status->callback([&context, flags] { context.action = [flags] { return RunStatus(*flags); }; });

  CLI::App* watch = build->add_subcommand("watch", "Follow a build to its end");
  AddRemoteOptions(watch, flags->remote);
  watch->add_option("build_id", flags->build_id, "Build id")->required();
  watch->add_option("--watch-seconds", flags->watch_seconds,
                    "Deadline of the watch (default one day)");
  watch->callback([&context, flags] {
    context.action = [flags]() -> absl::Status {
      auto stub = v1::Coordinator::NewStub(rpc::OpenChannel(flags->remote.address));
      return Watch(*stub, *flags, flags->build_id);
    };
  });

  CLI::App* cancel = build->add_subcommand("cancel", "Cancel a running build");
  AddRemoteOptions(cancel, flags->remote);
  cancel->add_option("build_id", flags->build_id, "Build id")->required();
  cancel->callback([&context, flags] { context.action = [flags] { return RunCancel(*flags); }; });

  CLI::App* list = build->add_subcommand("list", "The tenant's builds");
  AddRemoteOptions(list, flags->remote);
  list->callback([&context, flags] { context.action = [flags] { return RunList(*flags); }; });
}

}  // namespace fitbase::cli
