// fitbase loadtest: C concurrent clients calling the fit service for T seconds per phase: the
// empty call (the health check) as the machine's baseline, then FitGarment raw and Draco.
#include <algorithm>
#include <condition_variable>
#include <functional>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <thread>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"
#include "absl/time/clock.h"
#include "cli/api_key_source.h"
#include "cli/cli_context.h"
#include "cli/remote_flags.h"
#include "core/file_util.h"
#include "core/status_macros.h"
#include "fitbase/v1/fit_service.grpc.pb.h"
#include "grpcpp/alarm.h"
#include "grpcpp/generic/generic_stub.h"
#include "proto/json_codec.h"
#include "services/rpc/call_auth.h"
#include "services/rpc/channel.h"
#include "services/rpc/grpc_status.h"

namespace fitbase::cli {
namespace {

constexpr char kHealthCheck[] = "/grpc.health.v1.Health/Check";
// HealthCheckResponse{status: SERVING}, serialized.
constexpr char kServing[] = "\x08\x01";
constexpr absl::Duration kMaxBackoff = absl::Seconds(1);

struct LoadFlags {
  RemoteFlags remote{.address = "127.0.0.1:7402", .api_key_file = {}, .timeout_seconds = 5};
  std::string weights;
  std::string garment;
  std::string size = "M";
  std::string clients = "16";
  std::string encodings = "raw,draco";
  double seconds = 10;
  double backoff_ms = 250;
  int server_pid = 0;
  bool no_cleanup = false;
};

enum class Call { kHealth, kFitRaw, kFitDraco };

const char* CallName(Call call) {
  switch (call) {
    case Call::kHealth:
      return "health (empty)";
    case Call::kFitRaw:
      return "fit raw";
    case Call::kFitDraco:
      return "fit draco";
  }
  return "";
}

struct LoadResult {
  std::vector<double> served_ms;
  std::vector<double> refused_ms;  // RESOURCE_EXHAUSTED or UNAVAILABLE: the server's "not now".
  int64_t errors = 0;
  std::string first_error;
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

// The server's resident memory now and at its peak (MB), from /proc/<pid>/status.
struct Rss {
  double now_mb = 0;
  double peak_mb = 0;
};

absl::StatusOr<Rss> ServerRss(int pid) {
  ASSIGN_OR_RETURN(std::string status,
                   core::ReadFileToString(absl::StrCat("/proc/", pid, "/status")));
  Rss rss;
  for (absl::string_view line : absl::StrSplit(status, '\n')) {
    for (auto [field, value] : {std::pair{"VmRSS:", &rss.now_mb}, {"VmHWM:", &rss.peak_mb}}) {
      if (!absl::ConsumePrefix(&line, field)) continue;
      int64_t kb = 0;
      if (absl::SimpleAtoi(absl::StripSuffix(absl::StripAsciiWhitespace(line), " kB"), &kb)) {
        *value = kb / 1024.0;
      }
    }
  }
  return rss;
}

// One client: a connection of its own, as a separate shopper's, with one call in flight at a
// time, issued again from the previous call's completion, or after a backoff when the server
// refused it, doubling with each refusal in a row up to kMaxBackoff (gRPC's retry policy).
// Completions run on gRPC's threads, so hundreds of clients cost no blocked threads competing
// with the server for the cores.
class Client {
 public:
  Client(const std::string& address, const std::string& key, Call call,
         const v1::FitGarmentRequest& request, double timeout_seconds, absl::Duration backoff,
         uint64_t seed)
      : key_(key), call_(call), request_(request), timeout_(absl::Seconds(timeout_seconds)),
        backoff_(backoff), random_(seed) {
    grpc::ChannelArguments arguments;
    arguments.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
    arguments.SetMaxReceiveMessageSize(64 << 20);
    channel_ = grpc::CreateCustomChannel(rpc::ListenAddress(address),
                                         grpc::InsecureChannelCredentials(), arguments);
    stub_ = v1::FitService::NewStub(channel_);
    generic_ = std::make_unique<grpc::GenericStub>(channel_);
    grpc::Slice empty("");
    health_request_ = grpc::ByteBuffer(&empty, 1);
  }

  bool Connect(absl::Time deadline) {
    return channel_->WaitForConnected(absl::ToChronoTime(deadline));
  }

  void Start(absl::Time end, std::function<void()> on_done) {
    end_ = end;
    on_done_ = std::move(on_done);
    Issue();
  }

  LoadResult result;

 private:
  void Issue() {
    if (absl::Now() >= end_) {
      on_done_();
      return;
    }
    context_ = std::make_unique<grpc::ClientContext>();
    context_->set_deadline(absl::ToChronoTime(absl::Now() + timeout_));
    rpc::AddApiKey(*context_, key_);
    sent_ = absl::Now();
    auto done = [this](grpc::Status status) { Done(status); };
    if (call_ == Call::kHealth) {
      generic_->UnaryCall(context_.get(), kHealthCheck, grpc::StubOptions(), &health_request_,
                          &health_response_, done);
    } else {
      response_.Clear();
      stub_->async()->FitGarment(context_.get(), &request_, &response_, done);
    }
  }

  void Done(const grpc::Status& status) {
    const double ms = absl::ToDoubleMilliseconds(absl::Now() - sent_);
    if (status.ok() && call_ == Call::kHealth && !IsServing()) {
      Error("the health check did not answer SERVING");
    } else if (status.ok()) {
      backoff_now_ = backoff_;
      result.served_ms.push_back(ms);
      if (call_ != Call::kHealth) {
        result.response_bytes = response_.positions().ByteSizeLong();
        result.compute_us += response_.metrics().compute_us();
      }
    } else if (status.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED ||
               status.error_code() == grpc::StatusCode::UNAVAILABLE) {
      result.refused_ms.push_back(ms);
      // Jittered, so refused clients do not return in step.
      std::uniform_real_distribution<double> jitter(0.5, 1.5);
      alarm_.Set(absl::ToChronoTime(absl::Now() + backoff_now_ * jitter(random_)),
                 [this](bool) { Issue(); });
      backoff_now_ = std::min(2 * backoff_now_, kMaxBackoff);
      return;
    } else {
      Error(status.error_message());
    }
    Issue();
  }

  bool IsServing() {
    std::vector<grpc::Slice> slices;
    if (!health_response_.Dump(&slices).ok()) return false;
    std::string bytes;
    for (const grpc::Slice& slice : slices) {
      bytes.append(reinterpret_cast<const char*>(slice.begin()), slice.size());
    }
    return bytes == kServing;
  }

  void Error(const std::string& message) {
    if (result.errors++ == 0) result.first_error = message;
  }

  const std::string key_;
  const Call call_;
  const v1::FitGarmentRequest request_;
  const absl::Duration timeout_;
  const absl::Duration backoff_;
  absl::Duration backoff_now_ = backoff_;
  std::mt19937_64 random_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::FitService::Stub> stub_;
  std::unique_ptr<grpc::GenericStub> generic_;
  grpc::ByteBuffer health_request_;
  grpc::ByteBuffer health_response_;
  absl::Time end_;
  std::function<void()> on_done_;
  std::unique_ptr<grpc::ClientContext> context_;
  v1::FittedGarment response_;
  grpc::Alarm alarm_;
  absl::Time sent_;
};

absl::StatusOr<LoadResult> Run(const LoadFlags& flags, int client_count, Call call,
                               const std::string& key, const v1::FitGarmentRequest& request) {
  std::vector<std::unique_ptr<Client>> clients;
  for (int c = 0; c < client_count; ++c) {
    clients.push_back(std::make_unique<Client>(flags.remote.address, key, call, request,
                                               flags.remote.timeout_seconds,
                                               absl::Milliseconds(flags.backoff_ms), c + 1));
  }
  // Connected before the clock starts: the phase measures calls, not 256 handshakes.
  const absl::Time connect_deadline = absl::Now() + absl::Seconds(30);
  for (auto& client : clients) {
    if (!client->Connect(connect_deadline)) {
      return absl::UnavailableError(absl::StrCat("cannot connect to ", flags.remote.address));
    }
  }
  std::mutex mutex;
  std::condition_variable all_done;
  int running = client_count;
  const absl::Time start = absl::Now();
  const absl::Time end = start + absl::Seconds(flags.seconds);
  for (auto& client : clients) {
    client->Start(end, [&] {
      std::lock_guard lock(mutex);
      if (--running == 0) all_done.notify_all();
    });
  }
  {
    std::unique_lock lock(mutex);
    all_done.wait(lock, [&] { return running == 0; });
  }
  LoadResult result;
  result.seconds = absl::ToDoubleSeconds(absl::Now() - start);
  for (const auto& client : clients) {
    const LoadResult& one = client->result;
    result.served_ms.insert(result.served_ms.end(), one.served_ms.begin(), one.served_ms.end());
    result.refused_ms.insert(result.refused_ms.end(), one.refused_ms.begin(),
                             one.refused_ms.end());
    if (result.errors == 0) result.first_error = one.first_error;
    result.errors += one.errors;
    result.response_bytes = std::max(result.response_bytes, one.response_bytes);
    result.compute_us += one.compute_us;
  }
  return result;
}

absl::StatusOr<std::vector<int>> ParseClients(absl::string_view list) {
  std::vector<int> counts;
  for (absl::string_view item : absl::StrSplit(list, ',')) {
    int count = 0;
    if (!absl::SimpleAtoi(item, &count) || count < 1 || count > 1024) {
      return absl::InvalidArgumentError(
          absl::StrCat("--clients: '", item, "' is not a client count within [1, 1024]"));
    }
    counts.push_back(count);
  }
  return counts;
}

absl::StatusOr<std::vector<Call>> ParseEncodings(absl::string_view list) {
  std::vector<Call> calls = {Call::kHealth};
  for (absl::string_view item : absl::StrSplit(list, ',')) {
    if (item == "raw") {
      calls.push_back(Call::kFitRaw);
    } else if (item == "draco") {
      calls.push_back(Call::kFitDraco);
    } else {
      return absl::InvalidArgumentError(
          absl::StrCat("--encodings: unknown '", item, "'; expected raw and/or draco"));
    }
  }
  return calls;
}

absl::Status RunLoadtest(const LoadFlags& flags) {
  ASSIGN_OR_RETURN(const std::vector<int> client_counts, ParseClients(flags.clients));
  ASSIGN_OR_RETURN(const std::vector<Call> calls, ParseEncodings(flags.encodings));
  if (!(flags.seconds > 0 && flags.seconds <= 3600)) {
    return absl::InvalidArgumentError("--seconds must be within (0, 3600]");
  }
  if (!(flags.backoff_ms >= 0 && flags.backoff_ms <= 60000)) {
    return absl::InvalidArgumentError("--backoff-ms must be within [0, 60000]");
  }
  if (flags.server_pid != 0) RETURN_IF_ERROR(ServerRss(flags.server_pid).status());
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
      "FitGarment of %.12s size %s for %.0f s per phase on %s (%u cores); a refused client "
      "waits %.0f ms, doubling per refusal in a row up to 1 s, jittered x0.5-1.5; p99 ratio "
      "against the first client count\n\n",
      flags.garment, flags.size, flags.seconds, flags.remote.address,
      std::thread::hardware_concurrency(), flags.backoff_ms);
  std::cout << "| clients | call | served | calls/s | of health | refused/s | errors | p50 ms | "
               "p99 ms | p99 ratio | max ms | refusal p99 ms | fit us | response bytes | "
               "server RSS MB |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<std::optional<double>> first_p99(calls.size());
  std::optional<std::string> error;
  for (int client_count : client_counts) {
    double health_rate = 0;
    for (size_t c = 0; c < calls.size(); ++c) {
      const Call call = calls[c];
      request.set_encoding(call == Call::kFitDraco ? v1::POSITIONS_ENCODING_DRACO
                                                   : v1::POSITIONS_ENCODING_RAW);
      ASSIGN_OR_RETURN(LoadResult result, Run(flags, client_count, call, key, request));
      const double served = static_cast<double>(result.served_ms.size());
      const double rate = served / result.seconds;
      if (call == Call::kHealth) health_rate = rate;
      const double p50 = Percentile(result.served_ms, 0.50);
      const double p99 = Percentile(result.served_ms, 0.99);
      if (!first_p99[c].has_value()) first_p99[c] = p99;
      const double max = result.served_ms.empty() ? 0
                                                  : *std::max_element(result.served_ms.begin(),
                                                                      result.served_ms.end());
      std::string rss = "-";
      if (flags.server_pid != 0) {
        ASSIGN_OR_RETURN(Rss now, ServerRss(flags.server_pid));
        rss = absl::StrFormat("%.0f (peak %.0f)", now.now_mb, now.peak_mb);
      }
      std::cout << absl::StrFormat(
          "| %d | %s | %d | %.0f | %s | %.0f | %d | %.2f | %.2f | %.2f | %.2f | %s | %s | %s | "
          "%s |\n",
          client_count, CallName(call), result.served_ms.size(), rate,
          call == Call::kHealth ? "1" : absl::StrFormat("%.3f", rate / health_rate),
          result.refused_ms.size() / result.seconds, result.errors, p50, p99,
          *first_p99[c] > 0 ? p99 / *first_p99[c] : 0.0, max,
          result.refused_ms.empty()
              ? std::string("-")
              : absl::StrFormat("%.2f", Percentile(result.refused_ms, 0.99)),
          call == Call::kHealth ? "-" : absl::StrFormat("%.0f", served > 0
                                                                    ? result.compute_us / served
                                                                    : 0.0),
          call == Call::kHealth ? std::string("-") : absl::StrCat(result.response_bytes), rss);
      if (result.errors > 0 && !error.has_value()) {
        error = absl::StrCat(result.errors, " calls failed (", CallName(call), ", ",
                             client_count, " clients), first: ", result.first_error);
      }
    }
  }
  if (error.has_value()) return absl::InternalError(*error);
  return absl::OkStatus();
}

}  // namespace

void AddLoadtestCommand(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<LoadFlags>();
  CLI::App* command = app.add_subcommand(
      "loadtest",
      "Load the fit service: the health check, then FitGarment raw and Draco, per client count");
  AddRemoteOptions(command, flags->remote, "--server");
  command->add_option("--weights", flags->weights, "Weights JSON (customer project)")
      ->required();
  command->add_option("--garment", flags->garment, "Garment id")->required();
  command->add_option("--size", flags->size, "Size (default M)");
  command->add_option("--clients", flags->clients,
                      "Concurrent clients, a comma-separated list run in turn (default 16)");
  command->add_option("--encodings", flags->encodings, "raw and/or draco (default raw,draco)");
  command->add_option("--seconds", flags->seconds, "Seconds per phase (default 10)");
  command->add_option("--backoff-ms", flags->backoff_ms,
                      "A refused call's client waits this long, doubled per refusal in a row up "
                      "to 1 s and jittered, before its next call (default 250)");
  command->add_option("--server-pid", flags->server_pid,
                      "The server's process id, to report its resident memory (same machine)");
  command->add_flag("--no-cleanup", flags->no_cleanup, "Fit without the collision clean-up");
  command->callback(
      [&context, flags] { context.action = [flags] { return RunLoadtest(*flags); }; });
}

}  // namespace fitbase::cli
