// fitbase loadtest: C concurrent clients calling FitGarment for T seconds, raw and Draco.
#include <algorithm>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <iostream>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/time/clock.h"
#include "cli/api_key_source.h"
#include "cli/cli_context.h"
#include "cli/remote_flags.h"
#include "core/file_util.h"
#include "core/status_macros.h"
#include "fitbase/v1/fit_service.grpc.pb.h"
#include "proto/json_codec.h"
#include "services/rpc/call_auth.h"
#include "services/rpc/channel.h"
#include "services/rpc/grpc_status.h"

namespace fitbase::cli {
namespace {

struct LoadFlags {
  RemoteFlags remote{.address = "127.0.0.1:7402", .api_key_file = {}, .timeout_seconds = 5};
  std::string weights;
  std::string garment;
  std::string size = "M";
  int clients = 16;
  double seconds = 10;
  bool no_cleanup = false;
};

struct LoadResult {
  std::vector<double> latencies_ms;
  int64_t errors = 0;
  double seconds = 0;
  size_t response_bytes = 0;  // Of one response's positions.
  double compute_us = 0;
};

double Percentile(std::vector<double>& values, double p) {
  if (values.empty()) return 0;
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(p * values.size()));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

// One client: a connection of its own, as a separate shopper's, with one call in flight at a
// time, issued again from the previous call's completion. Completions run on gRPC's threads,
// so 16 clients cost no 16 blocked threads competing with the server for the cores.
class Client {
 public:
  Client(const std::string& address, const std::string& key,
         const v1::FitGarmentRequest& request, absl::Time end, double timeout_seconds,
         std::function<void()> on_done)
      : key_(key), request_(request), end_(end), timeout_(absl::Seconds(timeout_seconds)),
        on_done_(std::move(on_done)) {
    grpc::ChannelArguments arguments;
    arguments.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
    arguments.SetMaxReceiveMessageSize(64 << 20);
    stub_ = v1::FitService::NewStub(grpc::CreateCustomChannel(
        rpc::ListenAddress(address), grpc::InsecureChannelCredentials(), arguments));
  }

  void Start() { Issue(); }

  std::vector<double> latencies_ms;
  int64_t errors = 0;
  size_t response_bytes = 0;
  double compute_us = 0;  // Sum of the server's fit times.

 private:
  void Issue() {
    if (absl::Now() >= end_) {
      on_done_();
      return;
    }
    context_ = std::make_unique<grpc::ClientContext>();
    context_->set_deadline(absl::ToChronoTime(absl::Now() + timeout_));
    rpc::AddApiKey(*context_, key_);
    response_.Clear();
    sent_ = absl::Now();
    stub_->async()->FitGarment(context_.get(), &request_, &response_, [this](grpc::Status s) {
      if (s.ok()) {
        latencies_ms.push_back(absl::ToDoubleMilliseconds(absl::Now() - sent_));
        response_bytes = response_.positions().ByteSizeLong();
        compute_us += response_.metrics().compute_us();
      } else {
        ++errors;
      }
      Issue();
    });
  }

  const std::string key_;
  const v1::FitGarmentRequest request_;
  const absl::Time end_;
  const absl::Duration timeout_;
  const std::function<void()> on_done_;
  std::unique_ptr<v1::FitService::Stub> stub_;
  std::unique_ptr<grpc::ClientContext> context_;
  v1::FittedGarment response_;
  absl::Time sent_;
};

LoadResult Run(const LoadFlags& flags, const std::string& key,
               const v1::FitGarmentRequest& request) {
  std::mutex mutex;
  std::condition_variable all_done;
  int running = flags.clients;
  const absl::Time start = absl::Now();
  const absl::Time end = start + absl::Seconds(flags.seconds);
  std::vector<std::unique_ptr<Client>> clients;
  for (int c = 0; c < flags.clients; ++c) {
    clients.push_back(std::make_unique<Client>(flags.remote.address, key, request, end,
                                               flags.remote.timeout_seconds, [&] {
                                                 std::lock_guard lock(mutex);
                                                 if (--running == 0) all_done.notify_all();
                                               }));
  }
  for (auto& client : clients) client->Start();
  {
    std::unique_lock lock(mutex);
    all_done.wait(lock, [&] { return running == 0; });
  }
  LoadResult result;
  result.seconds = absl::ToDoubleSeconds(absl::Now() - start);
  for (const auto& client : clients) {
    result.latencies_ms.insert(result.latencies_ms.end(), client->latencies_ms.begin(),
                               client->latencies_ms.end());
    result.errors += client->errors;
    result.response_bytes = std::max(result.response_bytes, client->response_bytes);
    result.compute_us += client->compute_us;
  }
  return result;
}

absl::Status RunLoadtest(const LoadFlags& flags) {
  if (flags.clients < 1 || flags.clients > 1024) {
    return absl::InvalidArgumentError("--clients must be within [1, 1024]");
  }
  if (!(flags.seconds > 0 && flags.seconds <= 3600)) {
    return absl::InvalidArgumentError("--seconds must be within (0, 3600]");
  }
  ASSIGN_OR_RETURN(std::string key, flags.remote.api_key_file.empty()
                                        ? ApiKeyFromEnvironment()
                                        : ApiKeyFromFile(flags.remote.api_key_file));
  ASSIGN_OR_RETURN(std::string json, core::ReadFileToString(flags.weights));
  v1::FitGarmentRequest request;
  RETURN_IF_ERROR(proto::ParseJson(json, request.mutable_weights()));
  request.set_garment_id(flags.garment);
  request.set_size(flags.size);
  request.set_with_metrics(true);
  request.set_skip_cleanup(flags.no_cleanup);
  std::cout << absl::StrFormat(
      "FitGarment of %.12s size %s, %d clients for %.0f s each encoding, on %s (%u cores)\n\n",
      flags.garment, flags.size, flags.clients, flags.seconds, flags.remote.address,
      std::thread::hardware_concurrency());
  std::cout << "| encoding | calls | errors | calls/s | p50 ms | p99 ms | max ms | fit us | "
               "response bytes |\n|---|---|---|---|---|---|---|---|---|\n";
  size_t raw_bytes = 0;
  for (v1::PositionsEncoding encoding :
       {v1::POSITIONS_ENCODING_RAW, v1::POSITIONS_ENCODING_DRACO}) {
    request.set_encoding(encoding);
    LoadResult result = Run(flags, key, request);
    const size_t calls = result.latencies_ms.size();
    if (encoding == v1::POSITIONS_ENCODING_RAW) raw_bytes = result.response_bytes;
    const double p50 = Percentile(result.latencies_ms, 0.50);
    const double p99 = Percentile(result.latencies_ms, 0.99);
    const double max = result.latencies_ms.empty()
                           ? 0
                           : *std::max_element(result.latencies_ms.begin(),
                                               result.latencies_ms.end());
    std::cout << absl::StrFormat(
        "| %s | %d | %d | %.0f | %.2f | %.2f | %.2f | %.0f | %d%s |\n",
        encoding == v1::POSITIONS_ENCODING_RAW ? "raw float32" : "draco", calls, result.errors,
        calls / result.seconds, p50, p99, max, calls > 0 ? result.compute_us / calls : 0.0,
        result.response_bytes,
        encoding == v1::POSITIONS_ENCODING_DRACO && result.response_bytes > 0
            ? absl::StrFormat(" (%.1fx smaller)",
                              static_cast<double>(raw_bytes) / result.response_bytes)
            : std::string());
  }
  return absl::OkStatus();
}

}  // namespace

void AddLoadtestCommand(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<LoadFlags>();
  CLI::App* command = app.add_subcommand(
      "loadtest", "Load the fit service: concurrent FitGarment calls, raw and Draco");
  AddRemoteOptions(command, flags->remote, "--server");
  command->add_option("--weights", flags->weights, "Weights JSON (customer project)")
      ->required();
  command->add_option("--garment", flags->garment, "Garment id")->required();
  command->add_option("--size", flags->size, "Size (default M)");
  command->add_option("--clients", flags->clients, "Concurrent clients (default 16)");
  command->add_option("--seconds", flags->seconds, "Seconds per encoding (default 10)");
  command->add_flag("--no-cleanup", flags->no_cleanup, "Fit without the collision clean-up");
  command->callback(
      [&context, flags] { context.action = [flags] { return RunLoadtest(*flags); }; });
}

}  // namespace fitbase::cli
