// The fit server's admission on a real server on 127.0.0.1 over a real (empty) store: calls
// are held in flight by the test hook, so the limit is reached deterministically.
#include "services/fit/fit_server.h"

#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "services/rpc/call_auth.h"
#include "services/rpc/channel.h"

namespace fitbase::fit {
namespace {

using ::testing::HasSubstr;

constexpr char kCustomer[] = "fb_test_customer";

grpc::Status GetTopology(v1::FitService::Stub& stub) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
  rpc::AddApiKey(context, kCustomer);
  v1::GetGarmentTopologyRequest request;
  request.set_garment_id("no-such-garment");
  v1::GarmentTopology topology;
  return stub.GetGarmentTopology(&context, request, &topology);
}

TEST(FitServerTest, ACallBeyondTheLimitInFlightIsRefusedAtOnceAndTheHeldOnesServed) {
  const std::filesystem::path dir = core::ProcessTempDir() / "store";
  auto store = storage::AssetStore::Open(dir, {});
  ASSERT_TRUE(store.ok()) << store.status();

  std::mutex mutex;
  std::condition_variable changed;
  int entered = 0;
  bool released = false;
  FitServerOptions options;
  options.store = store->get();
  options.listen = "127.0.0.1:0";
  options.keys.AddKey(kCustomer, {"acme", rpc::Role::kCustomer});
  options.service.max_calls_in_flight = 2;
  options.service.threads = 2;
  options.service.before_call = [&] {
    std::unique_lock lock(mutex);
    ++entered;
    changed.notify_all();
    changed.wait(lock, [&] { return released; });
  };
  auto server = FitServer::Start(std::move(options));
  ASSERT_TRUE(server.ok()) << server.status();
  auto stub =
      v1::FitService::NewStub(rpc::OpenChannel(absl::StrCat("127.0.0.1:", (*server)->port())));

  std::vector<grpc::StatusCode> held(2, grpc::StatusCode::OK);
  std::vector<std::thread> callers;
  for (int i = 0; i < 2; ++i) {
    callers.emplace_back([&, i] { held[i] = GetTopology(*stub).error_code(); });
  }
  {
    std::unique_lock lock(mutex);
    changed.wait(lock, [&] { return entered == 2; });
  }
  const grpc::Status refused = GetTopology(*stub);
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(refused.error_message(), HasSubstr("limit of 2 calls"));
  {
    std::lock_guard lock(mutex);
    released = true;
  }
  changed.notify_all();
  for (std::thread& caller : callers) caller.join();
  // Served, not refused: the garment does not exist.
  EXPECT_EQ(held, std::vector<grpc::StatusCode>(2, grpc::StatusCode::NOT_FOUND));
  // Answered calls no longer count.
  EXPECT_EQ(GetTopology(*stub).error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(entered, 3);
  (*server)->Shutdown(absl::Seconds(1));
}

}  // namespace
}  // namespace fitbase::fit
