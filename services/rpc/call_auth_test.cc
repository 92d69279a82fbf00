#include "services/rpc/call_auth.h"

#include <grpcpp/create_channel.h>
#include <grpcpp/generic/async_generic_service.h>
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/security/server_credentials.h>
#include <grpcpp/server.h>
#include <grpcpp/server_builder.h>

#include <future>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "gtest/gtest.h"

namespace fitbase::rpc {
namespace {

constexpr absl::string_view kKey = "fb_test-key";

// Answers every call with AuthenticateCall's outcome: the principal in trailing metadata, or
// the error as the call's status.
class AuthService : public grpc::CallbackGenericService {
 public:
  explicit AuthService(const ApiKeyRegistry& keys) : keys_(keys) {}

  grpc::ServerGenericBidiReactor* CreateReactor(
      grpc::GenericCallbackServerContext* context) override {
    class Reactor : public grpc::ServerGenericBidiReactor {
     public:
      explicit Reactor(grpc::Status status) { Finish(status); }
      void OnDone() override { delete this; }
    };
    const absl::StatusOr<Principal> principal = AuthenticateCall(*context, keys_);
    if (!principal.ok()) {
      return new Reactor(grpc::Status(static_cast<grpc::StatusCode>(principal.status().code()),
                                      std::string(principal.status().message())));
    }
    context->AddTrailingMetadata("principal",
                                 absl::StrCat(principal->tenant, " ", RoleName(principal->role)));
    return new Reactor(grpc::Status::OK);
  }

 private:
  const ApiKeyRegistry& keys_;
};

class CallAuthTest : public testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<ApiKeyRegistry> keys =
        ApiKeyRegistry::Parse(absl::StrCat(HashApiKey(kKey), " acme ingestion\n"), "keys");
    ASSERT_TRUE(keys.ok()) << keys.status();
    keys_ = *std::move(keys);
    int port = 0;
    grpc::ServerBuilder builder;
    builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port);
    builder.RegisterCallbackGenericService(&service_);
    server_ = builder.BuildAndStart();
    ASSERT_NE(server_, nullptr);
    channel_ =
        grpc::CreateChannel(absl::StrCat("127.0.0.1:", port), grpc::InsecureChannelCredentials());
  }

  void TearDown() override {
    if (server_ != nullptr) server_->Shutdown();
  }

  // The principal the server saw ("<tenant> <role>"), or the call's error.
  grpc::Status Call(const std::vector<absl::string_view>& keys, std::string& principal) {
    grpc::ClientContext context;
    for (absl::string_view key : keys) AddApiKey(context, key);
    grpc::Slice slice("ping");
    const grpc::ByteBuffer request(&slice, 1);
    grpc::ByteBuffer response;
    std::promise<grpc::Status> done;
    grpc::GenericStub stub(channel_);
    stub.UnaryCall(&context, "/fitbase.test.Auth/Check", grpc::StubOptions(), &request, &response,
                   [&done](grpc::Status status) { done.set_value(status); });
    const grpc::Status status = done.get_future().get();
    const auto& trailers = context.GetServerTrailingMetadata();
    if (const auto it = trailers.find("principal"); it != trailers.end()) {
      principal.assign(it->second.data(), it->second.size());
    }
    return status;
  }

  ApiKeyRegistry keys_;
  AuthService service_{keys_};
  std::unique_ptr<grpc::Server> server_;
  std::shared_ptr<grpc::Channel> channel_;
};

TEST_F(CallAuthTest, AuthenticatesTheCallsKey) {
  std::string principal;
  const grpc::Status status = Call({kKey}, principal);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(principal, "acme ingestion");
}

TEST_F(CallAuthTest, RefusesMissingUnknownAndSeveralKeys) {
  struct Case {
    std::vector<absl::string_view> keys;
    std::string error;
  };
  const Case cases[] = {
      {{}, "missing API key"},
      {{"fb_other-key"}, "unknown API key"},
      {{kKey, kKey}, "several API keys"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.error);
    std::string principal;
    const grpc::Status status = Call(c.keys, principal);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_EQ(status.error_message(), c.error);
    EXPECT_EQ(principal, "");
  }
}

}  // namespace
}  // namespace fitbase::rpc
