#ifndef FITBASE_TESTS_BUILD_CLUSTER_H_
#define FITBASE_TESTS_BUILD_CLUSTER_H_

// What the distributed-build tests share: the small catalogue (tests/small_catalogue.sh),
// API keys of every role, and clients of a coordinator on 127.0.0.1.
#include <filesystem>
#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "core/file_util.h"
#include "fitbase/v1/avatar_basis.pb.h"
#include "fitbase/v1/catalog.grpc.pb.h"
#include "fitbase/v1/coordinator.grpc.pb.h"
#include "fitbase/v1/garment.pb.h"
#include "fitbase/v1/worker_queue.grpc.pb.h"
#include "grpcpp/grpcpp.h"
#include "gtest/gtest.h"
#include "proto/message_file.h"
#include "services/rpc/api_keys.h"
#include "services/rpc/call_auth.h"
#include "services/rpc/channel.h"

namespace fitbase {

inline std::filesystem::path SmallCatalogue() { return FITBASE_SMALL_CATALOGUE; }

// Keys of tenant "acme" by role, and an ingestion and a customer key of tenant "rival".
struct TestKeys {
  static constexpr char kAdmin[] = "fb_test_admin";
  static constexpr char kIngestion[] = "fb_test_ingestion";
  static constexpr char kCustomer[] = "fb_test_customer";
  static constexpr char kWorker[] = "fb_test_worker";
  static constexpr char kRival[] = "fb_test_rival";
  static constexpr char kRivalCustomer[] = "fb_test_rival_customer";

  static std::string FileText() {
    using rpc::HashApiKey;
    return absl::StrCat(HashApiKey(kAdmin), " acme admin\n", HashApiKey(kIngestion),
                        " acme ingestion\n", HashApiKey(kCustomer), " acme customer\n",
                        HashApiKey(kWorker), " workers worker\n", HashApiKey(kRival),
                        " rival ingestion\n", HashApiKey(kRivalCustomer), " rival customer\n");
  }
  static rpc::ApiKeyRegistry Registry() {
    return *rpc::ApiKeyRegistry::Parse(FileText(), "test keys");
  }
};

// A client context with `key` (none when empty) and a deadline.
inline std::unique_ptr<grpc::ClientContext> Call(const std::string& key, int seconds = 60) {
  auto context = std::make_unique<grpc::ClientContext>();
  context->set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(seconds));
  if (!key.empty()) rpc::AddApiKey(*context, key);
  return context;
}

struct Clients {
  explicit Clients(const std::string& address)
      : channel(rpc::OpenChannel(address)),
        coordinator(v1::Coordinator::NewStub(channel)),
        queue(v1::WorkerQueue::NewStub(channel)),
        catalog(v1::Catalog::NewStub(channel)) {}
  std::shared_ptr<grpc::Channel> channel;
  std::unique_ptr<v1::Coordinator::Stub> coordinator;
  std::unique_ptr<v1::WorkerQueue::Stub> queue;
  std::unique_ptr<v1::Catalog::Stub> catalog;
};

inline v1::AvatarBasis SmallBasis() {
  v1::AvatarBasis basis;
  EXPECT_TRUE(proto::ReadMessageFile(SmallCatalogue() / "b.fbb", &basis).ok());
  return basis;
}

inline v1::Garment SmallGarment() {
  v1::Garment garment;
  EXPECT_TRUE(proto::ReadMessageFile(SmallCatalogue() / "g.fbg", &garment).ok());
  return garment;
}

// The small basis published for acme as "women" over RPC.
inline void PublishSmallBasis(Clients& clients) {
  v1::PublishAvatarBasisRequest request;
  request.set_population("women");
  *request.mutable_basis() = SmallBasis();
  v1::PublishAvatarBasisResponse response;
  const grpc::Status status =
      clients.catalog->PublishAvatarBasis(Call(TestKeys::kAdmin).get(), request, &response);
  ASSERT_TRUE(status.ok()) << status.error_message();
}

// The build of size M, linear, with the fixture's short schedule.
inline v1::SubmitBuildRequest SmallBuild(const std::string& garment_id) {
  v1::SubmitBuildRequest request;
  request.mutable_request()->set_garment_id(garment_id);
  request.mutable_request()->add_sizes("M");
  request.mutable_request()->add_methods("linear");
  request.mutable_request()->set_homotopy_steps(2);
  request.mutable_request()->set_relax_steps(2);
  return request;
}

// Follows the build to its end and returns its last state.
inline v1::Build WatchToEnd(Clients& clients, const std::string& build_id) {
  v1::GetBuildRequest request;
  request.set_build_id(build_id);
  auto context = Call(TestKeys::kAdmin, 600);
  auto reader = clients.coordinator->WatchBuild(context.get(), request);
  v1::Build build;
  while (reader->Read(&build)) {
  }
  const grpc::Status status = reader->Finish();
  EXPECT_TRUE(status.ok()) << status.error_message();
  return build;
}

}  // namespace fitbase

#endif  // FITBASE_TESTS_BUILD_CLUSTER_H_
