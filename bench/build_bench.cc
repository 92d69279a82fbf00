// The distributed build's scaling on this machine:
//   fitbase_build_bench --data DIR [--garment female_sportsuit01] [--components 10]
//                       [--max-workers 2] [--homotopy-steps 20] [--relax-steps 5]
//                       [--queue-tasks 10000 --lease-workers 64 [--cached-plans 4]]
// Builds one garment's size M (2N + 1 drapes) through a real coordinator on 127.0.0.1 with
// 1, then 2, ... workers (one slot each, in this process), each run on a fresh store so no
// drape is a cache hit, and prints per run the wall time of the drapes, the speed-up over one
// worker, and the coordinator's overhead per task: the time a worker spends per task outside
// its drape (lease, spec transfer, completion, synced store writes), against the drape time.
//
// With --queue-tasks, the coordinator at scale instead: builds of sizes M and XL (each schedule
// another, so every task is a drape of its own) until that many tasks are queued, then
// --lease-workers workers with a stub drape (tests/stub_workers.h: lease, heartbeat, a
// completion under a foreign token, then the template positions as the result) leasing at once
// over gRPC. Prints the rates, this process's memory (coordinator and workers) queued and at
// the end, the store's size, and checks every task was leased once and completed once.
#include <filesystem>
#include <iostream>
#include <set>
#include <thread>

#include "CLI/CLI.hpp"
#include "absl/strings/ascii.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"
#include "absl/time/clock.h"
#include "body/body_model.h"
#include "core/file_util.h"
#include "core/status_macros.h"
#include "fitbase/v1/coordinator.grpc.pb.h"
#include "pipeline/avatar_basis_builder.h"
#include "pipeline/garment_importer.h"
#include "pipeline/population_folder.h"
#include "pipeline/progress_reporter.h"
#include "proto/message_file.h"
#include "services/build/coordinator_server.h"
#include "services/rpc/call_auth.h"
#include "services/rpc/channel.h"
#include "tests/stub_workers.h"
#include "workers/drape.h"
#include "workers/drape_worker.h"

namespace fitbase {
namespace {

constexpr char kAdminKey[] = "fb_bench_admin";
constexpr char kWorkerKey[] = "fb_bench_worker";

struct Flags {
  std::string data = "data/makehuman";
  std::string garment = "female_sportsuit01";
  int components = 10;
  int max_workers = 2;
  int homotopy_steps = workers::DrapeSchedule{}.homotopy_steps;
  int relax_steps = workers::DrapeSchedule{}.relax_steps;
  int queue_tasks = 0;
  int lease_workers = 64;
  int cached_plans = static_cast<int>(build::CoordinatorOptions{}.cached_plans);
};

struct Run {
  int workers = 0;
  double drape_wall_seconds = 0;  // Submit to the last drape stored.
  double total_seconds = 0;       // Submit to publication.
  double drape_seconds = 0;       // Sum of the drapes' own times.
  int tasks = 0;
};

// A coordinator on a fresh store at `db`, on a free port, with the bench's admin and worker keys.
build::CoordinatorServerOptions FreshServerOptions(const Flags& flags,
                                                   const std::filesystem::path& db) {
  std::filesystem::remove_all(db);
  build::CoordinatorServerOptions options;
  options.db = db;
  options.listen = "127.0.0.1:0";
  options.data_dir = flags.data;
  options.keys.AddKey(kAdminKey, {"bench", rpc::Role::kAdmin});
  options.keys.AddKey(kWorkerKey, {"bench", rpc::Role::kWorker});
  return options;
}

absl::StatusOr<Run> BuildWith(int worker_count, const Flags& flags, const v1::AvatarBasis& basis,
                              const v1::Garment& garment, const std::filesystem::path& db) {
  build::CoordinatorServerOptions options = FreshServerOptions(flags, db);
  auto server = build::CoordinatorServer::Start(std::move(options));
  if (!server.ok()) return server.status();
  storage::AssetStore& store = (*server)->store();
  if (absl::Status s = store.PublishAvatarBasis("bench", "women", basis.id(),
                                                proto::SerializeDeterministically(basis));
      !s.ok()) {
    return s;
  }
  if (absl::Status s =
          store.PutGarment("bench", garment.id(), proto::SerializeDeterministically(garment));
      !s.ok()) {
    return s;
  }
  const std::string address = absl::StrCat("127.0.0.1:", (*server)->port());
  std::vector<std::unique_ptr<workers::DrapeWorker>> pool;
  std::vector<std::thread> threads;
  for (int i = 0; i < worker_count; ++i) {
    workers::DrapeWorkerOptions worker;
    worker.coordinator = address;
    worker.api_key = kWorkerKey;
    worker.name = absl::StrCat("bench-", i);
    pool.push_back(std::make_unique<workers::DrapeWorker>(worker));
    threads.emplace_back([w = pool.back().get()] { w->Run(); });
  }
  auto stub = v1::Coordinator::NewStub(rpc::OpenChannel(address));
  v1::SubmitBuildRequest request;
  request.mutable_request()->set_garment_id(garment.id());
  request.mutable_request()->add_sizes("M");
  request.mutable_request()->set_homotopy_steps(static_cast<uint32_t>(flags.homotopy_steps));
  request.mutable_request()->set_relax_steps(static_cast<uint32_t>(flags.relax_steps));
  grpc::ClientContext submit_context;
  rpc::AddApiKey(submit_context, kAdminKey);
  submit_context.set_deadline(absl::ToChronoTime(absl::Now() + absl::Seconds(60)));
  v1::Build build;
  const absl::Time start = absl::Now();
  if (grpc::Status s = stub->SubmitBuild(&submit_context, request, &build); !s.ok()) {
    return absl::InternalError(s.error_message());
  }
  Run run{.workers = worker_count, .tasks = static_cast<int>(build.tasks_total())};
  grpc::ClientContext watch_context;
  rpc::AddApiKey(watch_context, kAdminKey);
  watch_context.set_deadline(absl::ToChronoTime(absl::Now() + absl::Hours(2)));
  v1::GetBuildRequest watch;
  watch.set_build_id(build.build_id());
  auto reader = stub->WatchBuild(&watch_context, watch);
  pipeline::ProgressReporter progress(absl::StrCat(worker_count, " worker(s): drapes"),
                                      run.tasks, std::cerr, pipeline::StderrIsTerminal());
  while (reader->Read(&build)) {
    progress.Update(build.tasks_done());
    if (run.drape_wall_seconds == 0 && build.tasks_done() == build.tasks_total()) {
      run.drape_wall_seconds = absl::ToDoubleSeconds(absl::Now() - start);
    }
  }
  progress.Finish();
  run.total_seconds = absl::ToDoubleSeconds(absl::Now() - start);
  reader->Finish();
  if (build.phase() != v1::BUILD_SUCCEEDED) {
    return absl::InternalError(absl::StrCat("build ended ", v1::BuildPhase_Name(build.phase()),
                                            ": ", build.error()));
  }
  v1::GetBuildRequest get;
  get.set_build_id(build.build_id());
  get.set_with_tasks(true);
  grpc::ClientContext get_context;
  rpc::AddApiKey(get_context, kAdminKey);
  get_context.set_deadline(absl::ToChronoTime(absl::Now() + absl::Seconds(60)));
  v1::GetBuildResponse tasks;
  stub->GetBuild(&get_context, get, &tasks);
  for (const v1::Task& task : tasks.tasks()) {
    v1::DrapeResult result;
    auto bytes = store.GetDrapeResult(task.drape_key());
    if (bytes.ok() && result.ParseFromString(*bytes))
      run.drape_seconds += result.report().seconds();
  }
  for (auto& worker : pool) worker->Drain();
  for (std::thread& thread : threads) thread.join();
  (*server)->Shutdown(absl::Seconds(1));
  return run;
}

// This process's resident memory now and at its peak, MB.
std::pair<double, double> MemoryMb() {
  double now = 0, peak = 0;
  const absl::StatusOr<std::string> status = core::ReadFileToString("/proc/self/status");
  if (!status.ok()) return {0, 0};
  for (absl::string_view line : absl::StrSplit(*status, '\n')) {
    for (auto [field, value] : {std::pair{"VmRSS:", &now}, {"VmHWM:", &peak}}) {
      int64_t kb = 0;
      if (absl::ConsumePrefix(&line, field) &&
          absl::SimpleAtoi(absl::StripSuffix(absl::StripAsciiWhitespace(line), " kB"), &kb)) {
        *value = kb / 1024.0;
      }
    }
  }
  return {now, peak};
}

uintmax_t FolderBytes(const std::filesystem::path& folder) {
  uintmax_t bytes = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
    if (entry.is_regular_file()) bytes += entry.file_size();
  }
  return bytes;
}

absl::Status ScaleRun(const Flags& flags, const v1::AvatarBasis& basis,
                      const v1::Garment& garment, const std::filesystem::path& db) {
  build::CoordinatorServerOptions options = FreshServerOptions(flags, db);
  options.coordinator.cached_plans = static_cast<size_t>(flags.cached_plans);
  ASSIGN_OR_RETURN(std::unique_ptr<build::CoordinatorServer> server,
                   build::CoordinatorServer::Start(std::move(options)));
  build::Coordinator& coordinator = server->coordinator();
  storage::AssetStore& store = server->store();
  RETURN_IF_ERROR(store.PublishAvatarBasis("bench", "women", basis.id(),
                                           proto::SerializeDeterministically(basis)));
  RETURN_IF_ERROR(
      store.PutGarment("bench", garment.id(), proto::SerializeDeterministically(garment)));
  const auto [start_mb, start_peak_mb] = MemoryMb();

  const absl::Time submit_start = absl::Now();
  std::vector<v1::Build> builds;
  int64_t queued = 0;
  for (uint32_t relax = 1; queued < flags.queue_tasks; ++relax) {
    v1::BuildRequest request;
    request.set_garment_id(garment.id());
    request.add_sizes("M");
    request.add_sizes("XL");
    request.set_homotopy_steps(static_cast<uint32_t>(flags.homotopy_steps));
    request.set_relax_steps(relax);
    ASSIGN_OR_RETURN(v1::Build build, coordinator.Submit("bench", request));
    queued += build.tasks_total() - build.tasks_done();
    builds.push_back(std::move(build));
  }
  const double submit_seconds = absl::ToDoubleSeconds(absl::Now() - submit_start);
  const auto [queued_mb, queued_peak_mb] = MemoryMb();

  const absl::Time lease_start = absl::Now();
  StubWorkers workers(absl::StrCat("127.0.0.1:", server->port()), kWorkerKey,
                      flags.lease_workers);
  pipeline::ProgressReporter progress("tasks leased and completed", queued, std::cerr,
                                      pipeline::StderrIsTerminal());
  for (const v1::Build& build : builds) {
    build::BuildSnapshot snapshot;
    while (snapshot.build.tasks_done() < build.tasks_total()) {
      ASSIGN_OR_RETURN(snapshot, coordinator.WaitForBuild("bench", build.build_id(),
                                                          snapshot.revision,
                                                          absl::Now() + absl::Minutes(10)));
      if (snapshot.build.phase() == v1::BUILD_FAILED) {
        return absl::InternalError(absl::StrCat("build ", build.build_id(), " failed: ",
                                                snapshot.build.error()));
      }
      progress.Update(workers.completed());
    }
  }
  const double lease_seconds = absl::ToDoubleSeconds(absl::Now() - lease_start);
  progress.Finish();
  const StubWorkers::Report report = workers.Stop();
  const auto [done_mb, peak_mb] = MemoryMb();

  int64_t leased_more_than_once = 0, not_stored = 0;
  std::set<std::string> keys;
  for (const v1::Build& build : builds) {
    ASSIGN_OR_RETURN(build::BuildSnapshot snapshot,
                     coordinator.GetBuild("bench", build.build_id(), /*with_tasks=*/true));
    for (const v1::Task& task : snapshot.tasks) {
      leased_more_than_once += task.phase() != v1::TASK_DONE || task.leases() != 1;
      not_stored += !store.GetDrapeResult(task.drape_key()).ok();
      keys.insert(task.drape_key());
    }
  }
  int64_t completed_twice = 0;
  for (const auto& [key, times] : report.completions) completed_twice += times != 1;
  const uintmax_t store_bytes = FolderBytes(db);
  const int64_t assembling = std::count_if(builds.begin(), builds.end(), [&](const v1::Build& b) {
    auto s = coordinator.GetBuild("bench", b.build_id(), false);
    return s.ok() && s->build.phase() == v1::BUILD_ASSEMBLING;
  });
  server->Shutdown(absl::Seconds(1));

  std::cout << absl::StrFormat(
      "coordinator at scale: %d builds of %s sizes M and XL (N = %d, %d drapes each), %d "
      "tasks queued, %d stub workers leasing at once over gRPC, %d plans cached, %u cores\n\n",
      builds.size(), flags.garment, basis.component_count(), builds[0].tasks_total(), queued,
      flags.lease_workers, flags.cached_plans, std::thread::hardware_concurrency());
  std::cout << "| figure | value |\n|---|---|\n";
  const auto row = [](absl::string_view name, const std::string& value) {
    std::cout << "| " << name << " | " << value << " |\n";
  };
  row("submit (plan, synced write) per build",
      absl::StrFormat("%.1f ms", 1e3 * submit_seconds / builds.size()));
  row("leased and completed", absl::StrFormat("%d tasks in %.1f s: %.0f tasks/s",
                                              report.completed, lease_seconds,
                                              report.completed / lease_seconds));
  row("RSS before submitting", absl::StrFormat("%.0f MB", start_mb));
  row("RSS with every task queued", absl::StrFormat("%.0f MB (+%.1f KB per task)", queued_mb,
                                                    1024 * (queued_mb - start_mb) / queued));
  row("RSS at the end, peak", absl::StrFormat("%.0f MB, %.0f MB", done_mb, peak_mb));
  row("store on disk", absl::StrFormat("%.0f MB (%.1f KB per drape result)",
                                       store_bytes / 1048576.0,
                                       store_bytes / 1024.0 / static_cast<double>(keys.size())));
  row("builds still assembling at the end", absl::StrCat(assembling));
  row("distinct drape keys / tasks", absl::StrCat(keys.size(), " / ", queued));
  row("tasks not done or leased more than once", absl::StrCat(leased_more_than_once));
  row("keys leased while another worker held them", absl::StrCat(report.concurrent_double_leases));
  row("completions accepted under a foreign token", absl::StrCat(report.foreign_tokens_accepted));
  row("keys completed other than once", absl::StrCat(completed_twice));
  row("results missing from the store", absl::StrCat(not_stored));
  row("failed worker calls",
      absl::StrCat(report.failed_calls,
                   report.failed_calls > 0 ? " (" + report.first_failure + ")" : std::string()));
  if (leased_more_than_once + report.concurrent_double_leases + report.foreign_tokens_accepted +
          completed_twice + not_stored + report.failed_calls >
      0 || static_cast<int64_t>(keys.size()) != queued) {
    return absl::InternalError("the lease rules were broken: see the table");
  }
  return absl::OkStatus();
}

absl::Status Main(const Flags& flags) {
  ASSIGN_OR_RETURN(body::BodyModel model, body::BodyModel::Load(flags.data));
  std::cerr << "avatar basis of 60 women with " << flags.components << " components...\n";
  ASSIGN_OR_RETURN(pipeline::Population population,
                   pipeline::SamplePopulation(model, body::PopulationPreset::kWomen, 1, 60));
  core::ComponentSelection selection;
  selection.rule = core::ComponentSelection::Rule::kCount;
  selection.count = flags.components;
  ASSIGN_OR_RETURN(v1::AvatarBasis basis, pipeline::BuildAvatarBasis(population, selection));
  const std::filesystem::path dir = std::filesystem::path(flags.data) / "clothes" / flags.garment;
  ASSIGN_OR_RETURN(pipeline::GarmentImportRequest import,
                   pipeline::ReadGarmentImportFiles(
                       {.mhclo = dir / (flags.garment + ".mhclo"), .obj = {}, .size_meshes = {}}));
  import.sizes = {"M"};
  if (flags.queue_tasks > 0) import.sizes.push_back("XL");
  ASSIGN_OR_RETURN(v1::Garment garment, pipeline::ImportGarment(model, basis, import));
  const std::filesystem::path scratch =
      std::filesystem::temp_directory_path() / absl::StrCat("fitbase-build-bench-", getpid());
  std::filesystem::create_directories(scratch);
  if (flags.queue_tasks > 0) {
    const absl::Status status = ScaleRun(flags, basis, garment, scratch / "db");
    std::filesystem::remove_all(scratch);
    return status;
  }
  std::vector<Run> runs;
  for (int workers = 1; workers <= flags.max_workers; ++workers) {
    ASSIGN_OR_RETURN(Run run, BuildWith(workers, flags, basis, garment,
                                        scratch / absl::StrCat("db-", workers)));
    runs.push_back(run);
  }
  std::filesystem::remove_all(scratch);

  std::cout << absl::StrFormat(
      "build of %s size M: %d drapes (N = %d), %d vertices, schedule %d + %d steps, %u cores\n\n",
      flags.garment, runs[0].tasks, flags.components, garment.template_mesh().vertex_count(),
      flags.homotopy_steps, flags.relax_steps, std::thread::hardware_concurrency());
  std::cout << "| workers | drapes wall s | with assembly s | mean drape s | speed-up | "
               "overhead per task ms | overhead / drape |\n|---|---|---|---|---|---|---|\n";
  for (const Run& run : runs) {
    const double mean_drape = run.drape_seconds / run.tasks;
    // Worker time per task not spent draping: slots x wall time, less the drapes, per task.
    const double overhead = (run.workers * run.drape_wall_seconds - run.drape_seconds) / run.tasks;
    std::cout << absl::StrFormat("| %d | %.2f | %.2f | %.3f | %.2f | %.1f | %.2f%% |\n",
                                 run.workers, run.drape_wall_seconds, run.total_seconds,
                                 mean_drape, runs[0].drape_wall_seconds / run.drape_wall_seconds,
                                 1e3 * overhead, 100 * overhead / mean_drape);
  }
  std::cout << "\nWith several workers the overhead also holds the idle tail: the last drapes "
               "run while other workers have nothing left.\n";
  return absl::OkStatus();
}

}  // namespace
}  // namespace fitbase

int main(int argc, char** argv) {
  CLI::App app{"fitbase distributed build scaling"};
  fitbase::Flags flags;
  app.add_option("--data", flags.data, "MakeHuman data folder");
  app.add_option("--garment", flags.garment, "Garment folder name under clothes/");
  app.add_option("--components", flags.components, "Avatar components N (2N + 1 drapes)");
  app.add_option("--max-workers", flags.max_workers, "Runs with 1..this many workers");
  app.add_option("--homotopy-steps", flags.homotopy_steps, "Drape schedule");
  app.add_option("--relax-steps", flags.relax_steps, "Drape schedule");
  app.add_option("--queue-tasks", flags.queue_tasks,
                 "The coordinator at scale instead: queue this many tasks first");
  app.add_option("--lease-workers", flags.lease_workers,
                 "At scale: stub workers leasing at once (default 64)");
  app.add_option("--cached-plans", flags.cached_plans,
                 "At scale: build plans the coordinator keeps (default 4)");
  CLI11_PARSE(app, argc, argv);
  if (const absl::Status status = fitbase::Main(flags); !status.ok()) {
    std::cerr << "fitbase_build_bench: " << status << "\n";
    return 1;
  }
  return 0;
}
