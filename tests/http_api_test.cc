// The HTTP API on a real fit server over a real (empty) RocksDB store, both on 127.0.0.1 with
// port 0: every bad request gets the API's JSON error with its HTTP status, and the server
// keeps answering. The browser tests (web/tests) cover the page with a built catalogue.
#include <filesystem>
#include <fstream>
#include <string>

#include "absl/strings/str_cat.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "services/fit/fit_server.h"
#include "services/http/http_server.h"
// Last: its <resolv.h> breaks Eigen's headers included after it.
#include "httplib.h"

namespace fitbase {
namespace {

using ::testing::HasSubstr;

constexpr char kCustomer[] = "fb_http_test_customer";

class HttpApiTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::filesystem::path dir = core::ProcessTempDir() / "http";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir / "web/node_modules/three/build");
    std::ofstream(dir / "web/index.html") << "<!doctype html><title>try on</title>";
    std::ofstream(dir / "web/node_modules/three/build/three.module.js") << "export {};";
    auto store = storage::AssetStore::Open(dir / "store", {});
    ASSERT_TRUE(store.ok()) << store.status();
    store_ = *std::move(store);
    fit::FitServerOptions fit;
    fit.store = store_.get();
    fit.listen = "127.0.0.1:0";
    fit.keys.AddKey(kCustomer, {"acme", rpc::Role::kCustomer});
    auto fit_server = fit::FitServer::Start(std::move(fit));
    ASSERT_TRUE(fit_server.ok()) << fit_server.status();
    fit_ = *std::move(fit_server);
    http::HttpServerOptions options;
    options.listen = "127.0.0.1:0";
    options.web_root = dir / "web";
    options.channel = fit_->InProcessChannel();
    options.max_body_bytes = 1 << 20;
    auto server = http::HttpServer::Start(std::move(options));
    ASSERT_TRUE(server.ok()) << server.status();
    http_ = *std::move(server);
    client_ = std::make_unique<httplib::Client>("127.0.0.1", http_->port());
  }
  void TearDown() override {
    if (http_) http_->Shutdown();
    if (fit_) fit_->Shutdown(absl::Seconds(1));
  }

  httplib::Headers Key() const { return {{"X-Api-Key", kCustomer}}; }

  std::unique_ptr<storage::AssetStore> store_;
  std::unique_ptr<fit::FitServer> fit_;
  std::unique_ptr<http::HttpServer> http_;
  std::unique_ptr<httplib::Client> client_;
};

// Status and the error's code and message.
void ExpectError(const httplib::Result& result, int status, const std::string& code,
                 const std::string& message) {
  ASSERT_TRUE(result) << "no answer";
  EXPECT_EQ(result->status, status) << result->body;
  EXPECT_EQ(result->get_header_value("Content-Type"), "application/json");
  EXPECT_THAT(result->body, HasSubstr(absl::StrCat("\"code\": \"", code, "\"")));
  EXPECT_THAT(result->body, HasSubstr(message));
}

TEST_F(HttpApiTest, ServesThePageAndItsModules) {
  auto page = client_->Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_THAT(page->body, HasSubstr("try on"));
  auto module = client_->Get("/vendor/three/build/three.module.js");
  ASSERT_TRUE(module);
  EXPECT_EQ(module->status, 200);
  EXPECT_EQ(module->get_header_value("Content-Type"), "text/javascript");
  ExpectError(client_->Get("/nothing-here.js"), 404, "NOT_FOUND", "/nothing-here.js");
}

TEST_F(HttpApiTest, EveryBadRequestIsAJsonErrorWithItsStatus) {
  ExpectError(client_->Get("/api/v1/garments"), 401, "UNAUTHENTICATED", "missing API key");
  ExpectError(client_->Get("/api/v1/garments", {{"X-Api-Key", "fb_wrong"}}), 401,
              "UNAUTHENTICATED", "");
  ExpectError(client_->Get("/api/v1/garments/no-such/topology", Key()), 404, "NOT_FOUND",
              "no-such");
  ExpectError(client_->Get("/api/v1/bodies/topology?population=elves", Key()), 404,
              "NOT_FOUND", "population 'elves'");
  ExpectError(client_->Post("/api/v1/fit", Key(), "{\"garment_id\": ", "application/json"), 400,
              "INVALID_ARGUMENT", "not a valid TryOnRequest");
  ExpectError(client_->Post("/api/v1/fit", Key(), "{\"garment_id\": \"g\", \"colour\": 1}",
                            "application/json"),
              400, "INVALID_ARGUMENT", "colour");
  ExpectError(client_->Post("/api/v1/bodies/project?population=women", Key(),
                            "v 1 2\nf 1 2 3\n", "text/plain"),
              400, "INVALID_ARGUMENT", "the uploaded OBJ");
  ExpectError(client_->Post("/api/v1/bodies/project?population=women", Key(), "\xff\x01garbage",
                            "application/octet-stream"),
              400, "INVALID_ARGUMENT", "not an avatar file");
  ExpectError(client_->Post("/api/v1/bodies/project?population=women", Key(),
                            std::string((1 << 20) + 1, 'v'), "text/plain"),
              413, "RESOURCE_EXHAUSTED", "limit of 1 MiB");
  ExpectError(client_->Post("/api/v1/bodies/from-measurements", Key(),
                            "{\"population\": \"women\", \"measurements\": {}}",
                            "application/json"),
              400, "INVALID_ARGUMENT", "stature");
  // Still answering.
  auto health = client_->Get("/healthz");
  ASSERT_TRUE(health);
  EXPECT_EQ(health->status, 200);
}

TEST_F(HttpApiTest, AKnownKeyOfAnEmptyShopListsNoGarments) {
  auto list = client_->Get("/api/v1/garments", Key());
  ASSERT_TRUE(list);
  EXPECT_EQ(list->status, 200) << list->body;
  EXPECT_EQ(list->body, "{\"garments\":[]}");
}

TEST_F(HttpApiTest, ServesHttpsWithTheServersCertificate) {
  const std::filesystem::path tls = std::filesystem::path(FITBASE_SOURCE_DIR) / "tests/testdata/tls";
  http::HttpServerOptions options;
  options.listen = "127.0.0.1:0";
  options.web_root = core::ProcessTempDir() / "http/web";
  options.channel = fit_->InProcessChannel();
  options.tls_cert = tls / "server.pem";
  options.tls_key = tls / "server.key";
  auto https = http::HttpServer::Start(std::move(options));
  ASSERT_TRUE(https.ok()) << https.status();
  httplib::SSLClient client("127.0.0.1", (*https)->port());
  client.set_ca_cert_path((tls / "ca.pem").c_str());
  // The test certificate names the coordinator's host, not 127.0.0.1: the chain is what is
  // checked here, so host name checking is left to the CA test of the gRPC servers.
  client.enable_server_certificate_verification(false);
  auto list = client.Get("/api/v1/garments", Key());
  ASSERT_TRUE(list) << httplib::to_string(list.error());
  EXPECT_EQ(list->status, 200);
  EXPECT_TRUE(list->body.starts_with("{\"garments\""));
  // Plain HTTP to the HTTPS port gets no answer.
  httplib::Client plain("127.0.0.1", (*https)->port());
  plain.set_read_timeout(5, 0);
  const httplib::Result answer = plain.Get("/healthz");
  EXPECT_FALSE(answer && answer->status == 200);
  (*https)->Shutdown();

  http::HttpServerOptions bad;
  bad.listen = "127.0.0.1:0";
  bad.web_root = core::ProcessTempDir() / "http/web";
  bad.channel = fit_->InProcessChannel();
  bad.tls_cert = tls / "server.pem";
  EXPECT_THAT(http::HttpServer::Start(bad).status(),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "both a certificate and a key"));
  bad.tls_key = tls / "intruder.key";  // Not the certificate's key.
  EXPECT_THAT(http::HttpServer::Start(bad).status(),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "HTTPS cannot start"));
}

TEST(HttpServerStartTest, RefusesAFolderWithoutThePageOrAnUnparsableAddress) {
  http::HttpServerOptions options;
  options.channel = grpc::CreateChannel("127.0.0.1:1", grpc::InsecureChannelCredentials());
  options.web_root = core::ProcessTempDir() / "no-page";
  options.listen = "127.0.0.1:0";
  EXPECT_THAT(http::HttpServer::Start(options).status(),
              core::StatusIs(absl::StatusCode::kNotFound, "has no index.html"));
  options.listen = "127.0.0.1:http";
  EXPECT_THAT(http::HttpServer::Start(options).status(),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "is not host:port"));
}

}  // namespace
}  // namespace fitbase
