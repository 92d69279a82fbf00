// fitbase serve: the coordinator, a worker, the fit service, or all in one process.
#include <signal.h>

#include <atomic>
#include <cstdlib>
#include <ctime>
#include <iostream>
#include <memory>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "cli/api_key_source.h"
#include "cli/cli_context.h"
#include "cli/remote_flags.h"
#include "core/log_line.h"
#include "core/status_macros.h"
#include "services/build/coordinator_server.h"
#include "services/fit/fit_server.h"
#include "services/http/http_server.h"
#include "services/rpc/channel.h"
#include "services/rpc/grpc_status.h"
#include "services/rpc/tls_credentials.h"
#include "workers/drape_worker.h"

namespace fitbase::cli {
namespace {

struct ServeFlags {
  std::string role;
  std::string db;
  std::string listen = "127.0.0.1:7401";
  std::string api_keys;
  double lease_seconds = 30;
  uint32_t max_attempts = 3;
  bool blob_files = true;
  std::string coordinator;
  int slots = 1;
  int workers = 2;
  std::string name;
  std::string api_key_file;
  double drain_seconds = 90;
  std::string fit_listen = "127.0.0.1:7402";
  std::string db_mode = "secondary";
  int64_t cache_mb = 1024;
  int max_calls = fit::FitServiceOptions{}.max_calls_in_flight;
  rpc::TlsFiles tls;
  std::string tls_target_name;
  std::string http_listen;
  std::string web_root = "web";
};

// Signals are taken by one thread with sigwait, so handlers never run inside gRPC or RocksDB.
sigset_t ShutdownSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGINT);
  return set;
}

// Waits for SIGTERM or SIGINT, at most `timeout` (negative: for ever); false on timeout.
bool WaitForSignal(const sigset_t& set, double timeout_seconds) {
  if (timeout_seconds < 0) {
    int signal = 0;
    sigwait(&set, &signal);
    return true;
  }
  timespec timeout{
      static_cast<time_t>(timeout_seconds),
      static_cast<long>((timeout_seconds - static_cast<time_t>(timeout_seconds)) * 1e9)};
  return sigtimedwait(&set, nullptr, &timeout) > 0;
}

absl::Status CheckCommon(const ServeFlags& flags) {
  if (flags.lease_seconds < 1 || flags.lease_seconds > 3600) {
    return absl::InvalidArgumentError("--lease-seconds must be within [1, 3600]");
  }
  if (flags.max_attempts < 1 || flags.max_attempts > 100) {
    return absl::InvalidArgumentError("--max-attempts must be within [1, 100]");
  }
  if (flags.slots < 1 || flags.slots > 256) {
    return absl::InvalidArgumentError("--slots must be within [1, 256]");
  }
  if (flags.cache_mb < 1 || flags.cache_mb > (int64_t{1} << 20)) {
    return absl::InvalidArgumentError("--cache-mb must be within [1, 1048576]");
  }
  if (flags.max_calls < 0 || flags.max_calls > 100000) {
    return absl::InvalidArgumentError("--max-calls must be within [0, 100000]");
  }
  if (flags.workers < 0 || flags.workers > 64) {
    return absl::InvalidArgumentError("--workers must be within [0, 64]");
  }
  return absl::OkStatus();
}

std::string DefaultWorkerName() {
  char host[256] = {};
  gethostname(host, sizeof(host) - 1);
  return absl::StrCat(host, "-", getpid());
}

absl::StatusOr<std::unique_ptr<build::CoordinatorServer>> StartCoordinator(
    const CliContext& context, const ServeFlags& flags, rpc::ApiKeyRegistry keys) {
  if (flags.db.empty()) return absl::InvalidArgumentError("--db is required for this role");
  build::CoordinatorServerOptions options;
  options.db = flags.db;
  options.listen = flags.listen;
  options.data_dir = ResolveDataDir(context);
  options.keys = std::move(keys);
  options.coordinator.lease = absl::Seconds(flags.lease_seconds);
  options.coordinator.max_attempts = flags.max_attempts;
  options.blob_files = flags.blob_files;
  if (!flags.tls.cert.empty() || !flags.tls.key.empty()) {
    ASSIGN_OR_RETURN(options.credentials, rpc::TlsServerCredentials(flags.tls));
  }
  ASSIGN_OR_RETURN(std::unique_ptr<build::CoordinatorServer> server,
                   build::CoordinatorServer::Start(std::move(options)));
  std::cout << "listening 127.0.0.1:" << server->port() << std::endl;
  return server;
}

workers::DrapeWorkerOptions WorkerOptions(const ServeFlags& flags, std::string coordinator,
                                          std::string key, std::string name) {
  workers::DrapeWorkerOptions options;
  options.coordinator = std::move(coordinator);
  options.api_key = std::move(key);
  options.slots = flags.slots;
  options.name = std::move(name);
  return options;
}

absl::Status ServeCoordinator(const CliContext& context, const ServeFlags& flags) {
  if (flags.api_keys.empty()) return absl::InvalidArgumentError("--api-keys is required");
  ASSIGN_OR_RETURN(rpc::ApiKeyRegistry keys, rpc::ApiKeyRegistry::Load(flags.api_keys));
  const sigset_t signals = ShutdownSignals();
  ASSIGN_OR_RETURN(std::unique_ptr<build::CoordinatorServer> server,
                   StartCoordinator(context, flags, std::move(keys)));
  WaitForSignal(signals, -1);
  core::LogLine("draining").Add("role", "coordinator");
  server->Shutdown(absl::Seconds(10));
  return absl::OkStatus();
}

// The worker drains on the first signal; on a second one, or when the drain outlasts
// --drain-seconds, it returns its leases and exits without waiting for its drapes.
absl::Status ServeWorkers(std::vector<std::unique_ptr<workers::DrapeWorker>>& pool,
                          const ServeFlags& flags, const sigset_t& signals) {
  std::vector<std::thread> threads;
  for (auto& worker : pool) threads.emplace_back([w = worker.get()] { w->Run(); });
  WaitForSignal(signals, -1);
  for (auto& worker : pool) worker->Drain();
  std::atomic<bool> drained = false;
  std::thread drain_guard([&] {
    // Either way the drain is over: a second signal or the time ran out; unless the workers
    // finished first and woke this thread to end it.
    WaitForSignal(signals, flags.drain_seconds);
    if (drained) return;
    for (auto& worker : pool) worker->ReturnLeases();
    core::LogLine("exiting").Add("reason", "drain cut short");
    std::_Exit(0);
  });
  for (std::thread& thread : threads) thread.join();
  // The guard must be gone before the pool is: a detached guard that woke during exit read
  // the destroyed pool (ASan, BuildFaultsTest under scripts/test.sh --sanitize). A signal
  // aimed at it ends its wait; SIGTERM is blocked in every thread, so only its sigwait sees it.
  drained = true;
  pthread_kill(drain_guard.native_handle(), SIGTERM);
  drain_guard.join();
  return absl::OkStatus();
}

absl::Status ServeWorker(const ServeFlags& flags) {
  if (flags.coordinator.empty()) return absl::InvalidArgumentError("--coordinator is required");
  ASSIGN_OR_RETURN(std::string key, flags.api_key_file.empty()
                                        ? ApiKeyFromEnvironment()
                                        : ApiKeyFromFile(flags.api_key_file));
  workers::DrapeWorkerOptions options =
      WorkerOptions(flags, rpc::ListenAddress(flags.coordinator), key,
                    flags.name.empty() ? DefaultWorkerName() : flags.name);
  if (!flags.tls.ca.empty() || !flags.tls.cert.empty()) {
    ASSIGN_OR_RETURN(options.credentials, rpc::TlsChannelCredentials(flags.tls));
    options.tls_target_name = flags.tls_target_name;
  }
  const sigset_t signals = ShutdownSignals();
  std::vector<std::unique_ptr<workers::DrapeWorker>> pool;
  pool.push_back(std::make_unique<workers::DrapeWorker>(std::move(options)));
  core::LogLine("worker_started").Add("coordinator", flags.coordinator).Add("slots", flags.slots);
  return ServeWorkers(pool, flags, signals);
}

fit::FitServerOptions FitOptions(const ServeFlags& flags, rpc::ApiKeyRegistry keys) {
  fit::FitServerOptions options;
  options.keys = std::move(keys);
  options.catalog.max_bytes = static_cast<size_t>(flags.cache_mb) << 20;
  options.service.max_calls_in_flight = flags.max_calls;
  return options;
}

// The page and its JSON API beside the fit service, when --http-listen asks for them; null
// otherwise. HTTPS with the server's --tls-cert and --tls-key when those are given.
absl::StatusOr<std::unique_ptr<http::HttpServer>> StartHttp(const ServeFlags& flags,
                                                            fit::FitServer& fit) {
  if (flags.http_listen.empty()) return nullptr;
  http::HttpServerOptions options;
  options.listen = flags.http_listen;
  options.web_root = flags.web_root;
  options.channel = fit.InProcessChannel();
  options.tls_cert = flags.tls.cert;
  options.tls_key = flags.tls.key;
  ASSIGN_OR_RETURN(std::unique_ptr<http::HttpServer> server,
                   http::HttpServer::Start(std::move(options)));
  std::cout << "http-listening 127.0.0.1:" << server->port() << std::endl;
  return server;
}

absl::Status ServeFit(const ServeFlags& flags) {
  if (flags.api_keys.empty()) return absl::InvalidArgumentError("--api-keys is required");
  if (flags.db.empty()) return absl::InvalidArgumentError("--db is required for this role");
  ASSIGN_OR_RETURN(rpc::ApiKeyRegistry keys, rpc::ApiKeyRegistry::Load(flags.api_keys));
  fit::FitServerOptions options = FitOptions(flags, std::move(keys));
  options.db = flags.db;
  options.listen = flags.listen;
  if (flags.db_mode == "secondary") {
    options.mode = storage::OpenMode::kSecondary;
    options.secondary_path = std::filesystem::temp_directory_path() /
                             absl::StrCat("fitbase-fit-secondary-", getpid());
  } else if (flags.db_mode == "readonly") {
    options.mode = storage::OpenMode::kReadOnly;
  } else {
    return absl::InvalidArgumentError(
        absl::StrCat("unknown --db-mode ", flags.db_mode, "; expected secondary or readonly"));
  }
  const sigset_t signals = ShutdownSignals();
  ASSIGN_OR_RETURN(std::unique_ptr<fit::FitServer> server,
                   fit::FitServer::Start(std::move(options)));
  std::cout << "listening 127.0.0.1:" << server->port() << std::endl;
  ASSIGN_OR_RETURN(std::unique_ptr<http::HttpServer> http, StartHttp(flags, *server));
  WaitForSignal(signals, -1);
  if (http != nullptr) http->Shutdown();
  server->Shutdown(absl::Seconds(5));
  return absl::OkStatus();
}

absl::Status ServeAll(const CliContext& context, const ServeFlags& flags) {
  if (flags.api_keys.empty()) return absl::InvalidArgumentError("--api-keys is required");
  ASSIGN_OR_RETURN(rpc::ApiKeyRegistry keys, rpc::ApiKeyRegistry::Load(flags.api_keys));
  // The in-process workers' key lives only in this process's memory.
  ASSIGN_OR_RETURN(std::string worker_key, rpc::NewApiKey());
  keys.AddKey(worker_key, rpc::Principal{"internal", rpc::Role::kWorker});
  const sigset_t signals = ShutdownSignals();
  rpc::ApiKeyRegistry fit_keys = keys;
  ASSIGN_OR_RETURN(std::unique_ptr<build::CoordinatorServer> server,
                   StartCoordinator(context, flags, std::move(keys)));
  fit::FitServerOptions fit_options = FitOptions(flags, std::move(fit_keys));
  fit_options.store = &server->store();
  fit_options.listen = flags.fit_listen;
  ASSIGN_OR_RETURN(std::unique_ptr<fit::FitServer> fit,
                   fit::FitServer::Start(std::move(fit_options)));
  std::cout << "fit-listening 127.0.0.1:" << fit->port() << std::endl;
  ASSIGN_OR_RETURN(std::unique_ptr<http::HttpServer> http, StartHttp(flags, *fit));
  std::vector<std::unique_ptr<workers::DrapeWorker>> pool;
  for (int i = 0; i < flags.workers; ++i) {
    pool.push_back(std::make_unique<workers::DrapeWorker>(
        WorkerOptions(flags, absl::StrCat("127.0.0.1:", server->port()), worker_key,
                      absl::StrCat("worker-", i))));
  }
  const absl::Status status = ServeWorkers(pool, flags, signals);
  if (http != nullptr) http->Shutdown();
  fit->Shutdown(absl::Seconds(5));
  server->Shutdown(absl::Seconds(10));
  return status;
}

absl::Status RunServe(const CliContext& context, const ServeFlags& flags) {
  RETURN_IF_ERROR(CheckCommon(flags));
  // Before any thread starts, so every thread inherits the mask and only sigwait sees them.
  const sigset_t signals = ShutdownSignals();
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  if (flags.role == "coordinator") return ServeCoordinator(context, flags);
  if (flags.role == "worker") return ServeWorker(flags);
  if (flags.role == "all") return ServeAll(context, flags);
  if (flags.role == "fit") return ServeFit(flags);
  return absl::InvalidArgumentError(absl::StrCat("unknown --role ", flags.role,
                                                 "; expected coordinator, worker, fit or all"));
}

}  // namespace

void AddServeCommand(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<ServeFlags>();
  CLI::App* command =
      app.add_subcommand("serve", "Run the coordinator, a worker, the fit service, or all");
  command->add_option("--role", flags->role, "coordinator, worker, fit or all")->required();
  command->add_option("--db", flags->db, "coordinator, fit, all: the RocksDB store folder");
  command->add_option("--fit-listen", flags->fit_listen,
                      "all: host:port of the fit service (default 127.0.0.1:7402)");
  command->add_option("--http-listen", flags->http_listen,
                      "fit, all: also serve the try-on page and its JSON API on host:port "
                      "(port 0: any free port; docs/http-api.md)");
  command->add_option("--web-root", flags->web_root,
                      "fit, all: the page's folder, with three.js installed under it "
                      "(default: web)");
  command->add_option("--db-mode", flags->db_mode,
                      "fit: secondary (of a live coordinator's store, created with "
                      "--blob-files false) or readonly (a checkpoint); default secondary");
  command->add_option("--cache-mb", flags->cache_mb,
                      "fit, all: cache of parsed bases, MB (default 1024)");
  command->add_option("--max-calls", flags->max_calls,
                      "fit, all: fit calls admitted at once (running or queued); more are "
                      "RESOURCE_EXHAUSTED at once (default 0: 8 per core)");
  command->add_option("--listen", flags->listen,
                      "coordinator, fit, all: host:port to serve on (port 0: any free port; "
                      "default 127.0.0.1:7401)");
  command->add_option("--api-keys", flags->api_keys,
                      "coordinator, fit, all: key file (`fitbase keys add`)");
  command->add_option("--lease-seconds", flags->lease_seconds,
                      "coordinator, all: lease duration without heartbeat (default 30)");
  command->add_option("--max-attempts", flags->max_attempts,
                      "coordinator, all: failed attempts before a task fails (default 3)");
  command->add_option("--blob-files", flags->blob_files,
                      "coordinator, all: large values in blob files when the store is created "
                      "(default true; false lets RocksDB secondaries read it)");
  command->add_option("--coordinator", flags->coordinator, "worker: the coordinator's host:port");
  command->add_option("--slots", flags->slots, "worker, all: drapes run side by side (default 1)");
  command->add_option("--workers", flags->workers, "all: in-process workers (default 2)");
  command->add_option("--name", flags->name, "worker: name in leases and logs (default host-pid)");
  command->add_option("--api-key-file", flags->api_key_file,
                      "worker: file holding its key (default: $FITBASE_API_KEY)");
  command->add_option("--tls-cert", flags->tls.cert,
                      "coordinator, worker: this side's TLS certificate chain (PEM)");
  command->add_option("--tls-key", flags->tls.key, "coordinator, worker: its private key (PEM)");
  command->add_option("--tls-ca", flags->tls.ca,
                      "coordinator: require client certificates signed by this CA (mutual "
                      "TLS); worker: the CA that signed the coordinator's certificate");
  command->add_option("--tls-target-name", flags->tls_target_name,
                      "worker: the name on the coordinator's certificate, if not its host");
  command->add_option("--drain-seconds", flags->drain_seconds,
                      "worker, all: after SIGTERM, how long running drapes may take before "
                      "their leases are returned (default 90)");
  command->callback([&context, flags] {
    context.action = [&context, flags] { return RunServe(context, *flags); };
  });
}

}  // namespace fitbase::cli
