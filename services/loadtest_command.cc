// fitbase loadtest: C concurrent clients calling FitGarment for T seconds, raw and Draco.
#include <algorithm>
#include <atomic>
#include <iostream>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/time/clock.h"
#include "core/file_util.h"
#include "core/status_macros.h"
#include "fitbase/v1/fit_service.grpc.pb.h"
#include "proto/json_codec.h"
#include "services/api_key_source.h"
#include "services/call_auth.h"
#include "services/cli_context.h"
#include "services/grpc_client.h"

namespace fitbase::services {
namespace {

struct LoadFlags {
  RemoteFlags remote{.address = "127.0.0.1:7402", .api_key_file = {}, .timeout_seconds = 5};
  std::string weights;
  std::string garment;
  std::string size = "M";
  int clients = 16;
  double seconds = 10;
};

struct LoadResult {
  std::vector<double> latencies_ms;
  int64_t errors = 0;
  double seconds = 0;
  size_t response_bytes = 0;  // Of one response's positions.
};

double Percentile(std::vector<double>& values, double p) {
  if (values.empty()) return 0;
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(p * values.size()));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

// Each client has its own channel (its own connection), as separate shoppers would.
LoadResult Run(const LoadFlags& flags, const std::string& key, const v1::FitGarmentRequest& request) {
  std::vector<std::vector<double>> latencies(static_cast<size_t>(flags.clients));
  std::atomic<int64_t> errors{0};
  std::atomic<size_t> response_bytes{0};
  const absl::Time start = absl::Now();
  const absl::Time end = start + absl::Seconds(flags.seconds);
  std::vector<std::thread> threads;
  for (int c = 0; c < flags.clients; ++c) {
    threads.emplace_back([&, c] {
      grpc::ChannelArguments arguments;
      arguments.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
      arguments.SetMaxReceiveMessageSize(64 << 20);
      auto stub = v1::FitService::NewStub(grpc::CreateCustomChannel(
          ListenAddress(flags.remote.address), grpc::InsecureChannelCredentials(), arguments));
      while (absl::Now() < end) {
        grpc::ClientContext context;
        context.set_deadline(absl::ToChronoTime(absl::Now() + absl::Seconds(flags.remote.timeout_seconds)));
        AddApiKey(context, key);
        v1::FittedGarment fitted;
        const absl::Time sent = absl::Now();
        const grpc::Status status = stub->FitGarment(&context, request, &fitted);
        const double ms = absl::ToDoubleMilliseconds(absl::Now() - sent);
        if (!status.ok()) {
          ++errors;
          continue;
        }
        latencies[static_cast<size_t>(c)].push_back(ms);
        response_bytes.store(fitted.positions().ByteSizeLong());
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  LoadResult result;
  result.seconds = absl::ToDoubleSeconds(absl::Now() - start);
  for (const auto& client : latencies) {
    result.latencies_ms.insert(result.latencies_ms.end(), client.begin(), client.end());
  }
  result.errors = errors.load();
  result.response_bytes = response_bytes.load();
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
  std::cout << absl::StrFormat(
      "FitGarment of %.12s size %s, %d clients for %.0f s each encoding, on %s (%u cores)\n\n",
      flags.garment, flags.size, flags.clients, flags.seconds, flags.remote.address,
      std::thread::hardware_concurrency());
  std::cout << "| encoding | calls | errors | calls/s | p50 ms | p99 ms | max ms | response "
               "bytes |\n|---|---|---|---|---|---|---|---|\n";
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
        "| %s | %d | %d | %.0f | %.2f | %.2f | %.2f | %d%s |\n",
        encoding == v1::POSITIONS_ENCODING_RAW ? "raw float32" : "draco", calls, result.errors,
        calls / result.seconds, p50, p99, max, result.response_bytes,
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
  command->callback(
      [&context, flags] { context.action = [flags] { return RunLoadtest(*flags); }; });
}

}  // namespace fitbase::services
