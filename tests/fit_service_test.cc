// The fit service end to end: a real coordinator and workers build the small catalogue's
// clothing basis into a real RocksDB store, and a real fit server on 127.0.0.1 answers a
// customer's calls, compared with the local `fitbase fit`.
#include <cmath>
#include <limits>
#include <thread>

#include "absl/strings/str_format.h"

#include "body/body_measurements.h"
#include "body/body_model.h"
#include "cli/customer_client.h"
#include "core/garment_obj.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "pipeline/avatar_file.h"
#include "pipeline/avatar_from_measurements.h"
#include "proto/avatar_codec.h"
#include "proto/draco_codec.h"
#include "proto/json_codec.h"
#include "services/build/coordinator_server.h"
#include "services/fit/fit_server.h"
#include "services/rpc/clock.h"
#include "tests/build_cluster.h"
#include "tests/cli_runner.h"
#include "workers/drape_worker.h"

namespace fitbase {
namespace {

using ::testing::HasSubstr;

class FitServiceTest : public ::testing::Test {
 protected:
  // One build per test process: each TEST runs in its own process under ctest.
  void SetUp() override {
    ASSERT_TRUE(std::filesystem::exists(SmallCatalogue() / "ready"));
    dir_ = core::ProcessTempDir() / "fit";
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    build::CoordinatorServerOptions options;
    options.db = dir_ / "db";
    options.listen = "127.0.0.1:0";
    options.data_dir = core::TestDataDir();
    options.keys = TestKeys::Registry();
    auto coordinator = build::CoordinatorServer::Start(std::move(options));
    ASSERT_TRUE(coordinator.ok()) << coordinator.status();
    coordinator_ = *std::move(coordinator);
    Clients clients(absl::StrCat("127.0.0.1:", coordinator_->port()));
    PublishSmallBasis(clients);
    garment_ = SmallGarment();
    ASSERT_TRUE(coordinator_->store()
                    .PutGarment("acme", garment_.id(), proto::SerializeDeterministically(garment_))
                    .ok());
    workers::DrapeWorkerOptions worker_options;
    worker_options.coordinator = absl::StrCat("127.0.0.1:", coordinator_->port());
    worker_options.api_key = TestKeys::kWorker;
    worker_options.name = "w";
    worker_options.slots = 2;
    workers::DrapeWorker worker(worker_options);
    std::thread thread([&] { worker.Run(); });
    v1::Build build;
    ASSERT_TRUE(clients.coordinator
                    ->SubmitBuild(Call(TestKeys::kAdmin).get(), SmallBuild(garment_.id()), &build)
                    .ok());
    ASSERT_EQ(WatchToEnd(clients, build.build_id()).phase(), v1::BUILD_SUCCEEDED);
    worker.Drain();
    thread.join();

    fit::FitServerOptions fit;
    fit.store = &coordinator_->store();
    fit.listen = "127.0.0.1:0";
    fit.keys = TestKeys::Registry();
    fit.catalog.clock = &clock_;
    auto server = fit::FitServer::Start(std::move(fit));
    ASSERT_TRUE(server.ok()) << server.status();
    fit_ = *std::move(server);
    stub_ = v1::FitService::NewStub(rpc::OpenChannel(absl::StrCat("127.0.0.1:", fit_->port())));
  }
  void TearDown() override {
    if (fit_ != nullptr) fit_->Shutdown(absl::Seconds(1));
    if (coordinator_ != nullptr) coordinator_->Shutdown(absl::Seconds(1));
  }

  v1::ProjectAvatarRequest AvatarRequest(int index, bool draco) {
    auto avatar = pipeline::ReadAvatarObj(SmallCatalogue() / "pop" /
                                          absl::StrFormat("avatar-%05d.obj", index));
    EXPECT_TRUE(avatar.ok());
    v1::ProjectAvatarRequest request;
    request.set_population("women");
    *request.mutable_avatar() = *proto::AvatarFromPositions(avatar->positions, draco);
    return request;
  }

  v1::AvatarProjection Project(int index, const std::string& key = TestKeys::kCustomer) {
    v1::AvatarProjection projection;
    const grpc::Status status =
        stub_->ProjectAvatar(Call(key).get(), AvatarRequest(index, false), &projection);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return projection;
  }

  v1::FitGarmentRequest FitRequest(const v1::AvatarWeights& weights) {
    v1::FitGarmentRequest request;
    *request.mutable_weights() = weights;
    request.set_garment_id(garment_.id());
    request.set_size("M");
    request.set_with_metrics(true);
    return request;
  }

  grpc::StatusCode FitCode(const v1::FitGarmentRequest& request,
                           const std::string& key = TestKeys::kCustomer) {
    v1::FittedGarment fitted;
    return stub_->FitGarment(Call(key).get(), request, &fitted).error_code();
  }

  // Five measurements of population avatar `index`, to a millimetre as a person types them:
  // a body the basis's population holds.
  v1::TypedMeasurements MeasurementsOf(int index) {
    auto avatar = pipeline::ReadAvatarObj(SmallCatalogue() / "pop" /
                                          absl::StrFormat("avatar-%05d.obj", index));
    EXPECT_TRUE(avatar.ok());
    auto measured = body::MeasureBody(*avatar);
    EXPECT_TRUE(measured.ok()) << measured.status();
    const v1::TypedMeasurements all = pipeline::MeasurementsToProto(*measured);
    const auto typed = [](double value) { return std::round(10 * value) / 10; };
    v1::TypedMeasurements five;
    five.set_stature_cm(typed(all.stature_cm()));
    five.set_weight_kg(typed(all.weight_kg()));
    five.set_bust_girth_cm(typed(all.bust_girth_cm()));
    five.set_waist_girth_cm(typed(all.waist_girth_cm()));
    five.set_hip_girth_cm(typed(all.hip_girth_cm()));
    return five;
  }

  grpc::Status FromMeasurements(const v1::TypedMeasurements& measurements,
                                v1::AvatarFromMeasurementsResponse* response,
                                const std::string& population = "women",
                                v1::PositionsEncoding encoding = v1::POSITIONS_ENCODING_DRACO,
                                const std::string& key = TestKeys::kCustomer) {
    v1::AvatarFromMeasurementsRequest request;
    *request.mutable_measurements() = measurements;
    request.set_population(population);
    request.set_encoding(encoding);
    return stub_->AvatarFromMeasurements(Call(key).get(), request, response);
  }

  rpc::ManualClock clock_{absl::FromUnixSeconds(1800000000)};
  std::filesystem::path dir_;
  std::unique_ptr<build::CoordinatorServer> coordinator_;
  std::unique_ptr<fit::FitServer> fit_;
  std::unique_ptr<v1::FitService::Stub> stub_;
  v1::Garment garment_;
};

TEST_F(FitServiceTest, AFitOverGrpcMatchesTheLocalFitWithinTheDracoQuantization) {
  const v1::AvatarProjection projection = Project(3);
  EXPECT_EQ(projection.weights().basis_id(), garment_.avatar_basis_id());
  EXPECT_FALSE(projection.out_of_distribution());
  v1::FittedGarment draco;
  ASSERT_TRUE(stub_->FitGarment(Call(TestKeys::kCustomer).get(), FitRequest(projection.weights()),
                                &draco)
                  .ok());
  v1::FitGarmentRequest raw_request = FitRequest(projection.weights());
  raw_request.set_encoding(v1::POSITIONS_ENCODING_RAW);
  v1::FittedGarment raw;
  ASSERT_TRUE(stub_->FitGarment(Call(TestKeys::kCustomer).get(), raw_request, &raw).ok());
  EXPECT_EQ(draco.clothing_basis_version(), 1u);
  const int64_t vertices = garment_.template_mesh().vertex_count();
  v1::GetGarmentTopologyRequest topology_request;
  topology_request.set_garment_id(garment_.id());
  v1::GarmentTopology topology;
  ASSERT_TRUE(
      stub_->GetGarmentTopology(Call(TestKeys::kCustomer).get(), topology_request, &topology).ok());
  auto wire = proto::DecodePositions(draco.positions(), vertices);
  ASSERT_TRUE(wire.ok());
  auto from_draco = cli::FromWireOrder(topology, *wire);
  auto from_raw = proto::DecodePositions(raw.positions(), vertices);
  ASSERT_TRUE(from_draco.ok() && from_raw.ok());
  EXPECT_GE(raw.positions().ByteSizeLong(), 4 * draco.positions().ByteSizeLong());

  const Result local = RunFitbase(
      {"fit", "--clothing", (SmallCatalogue() / "M-linear.fbc").string(), "--avatar",
       (SmallCatalogue() / "pop" / "avatar-00003.obj").string(), "--basis",
       (SmallCatalogue() / "b.fbb").string(), "--out", (dir_ / "local.obj").string()});
  ASSERT_EQ(local.exit_code, 0) << local.err;
  auto expected = core::ReadGarmentObj(dir_ / "local.obj");
  ASSERT_TRUE(expected.ok());
  const float bound = draco.positions().draco().max_error_m();
  double worst_raw = 0, worst_draco = 0;
  for (int64_t i = 0; i < 3 * vertices; ++i) {
    const double want = expected->mesh.positions.data()[i];
    worst_raw = std::max(worst_raw, std::abs((*from_raw)[i] - want));
    worst_draco = std::max(worst_draco, std::abs((*from_draco)[i] - want));
  }
  EXPECT_LT(worst_raw, 1e-5);  // The OBJ's printed digits and float32 projections.
  EXPECT_LT(worst_draco, bound + 1e-5);
}

TEST_F(FitServiceTest, AFitToTheOwnMeshFollowsItAndMatchesTheLocalFit) {
  const v1::AvatarProjection projection = Project(3);
  const v1::ProjectAvatarRequest own = AvatarRequest(3, /*draco=*/false);
  v1::FitGarmentRequest request = FitRequest(projection.weights());
  request.set_encoding(v1::POSITIONS_ENCODING_RAW);
  v1::FittedGarment of_weights;
  ASSERT_TRUE(stub_->FitGarment(Call(TestKeys::kCustomer).get(), request, &of_weights).ok());
  *request.mutable_body() = own.avatar();
  v1::FittedGarment on_own;
  ASSERT_TRUE(stub_->FitGarment(Call(TestKeys::kCustomer).get(), request, &on_own).ok());
  const int64_t vertices = garment_.template_mesh().vertex_count();
  auto a = proto::DecodePositions(of_weights.positions(), vertices);
  auto b = proto::DecodePositions(on_own.positions(), vertices);
  ASSERT_TRUE(a.ok() && b.ok());
  double moved = 0;
  for (int64_t i = 0; i < 3 * vertices; ++i) {
    moved = std::max(moved, static_cast<double>(std::abs((*a)[i] - (*b)[i])));
  }
  EXPECT_GT(moved, 1e-4);  // The projection leaves millimetres out of the body.

  const Result local = RunFitbase(
      {"fit", "--clothing", (SmallCatalogue() / "M-linear.fbc").string(), "--avatar",
       (SmallCatalogue() / "pop" / "avatar-00003.obj").string(), "--basis",
       (SmallCatalogue() / "b.fbb").string(), "--fit-body", "own", "--out",
       (dir_ / "local.obj").string()});
  ASSERT_EQ(local.exit_code, 0) << local.err;
  EXPECT_THAT(local.out, HasSubstr("to the avatar's own mesh"));
  auto expected = core::ReadGarmentObj(dir_ / "local.obj");
  ASSERT_TRUE(expected.ok());
  double worst = 0;
  for (int64_t i = 0; i < 3 * vertices; ++i) {
    worst = std::max(worst, std::abs((*b)[i] - expected->mesh.positions.data()[i]));
  }
  EXPECT_LT(worst, 1e-5);

  // The customer command sends the mesh with the weights.
  const std::filesystem::path key = dir_ / "customer.key";
  ASSERT_TRUE(core::WriteFileAtomically(key, absl::StrCat(TestKeys::kCustomer, "\n")).ok());
  ASSERT_TRUE(core::WriteFileAtomically(dir_ / "w.json", proto::ToJson(projection.weights())).ok());
  const Result remote = RunFitbase(
      {"customer", "fit", "--server", absl::StrCat("127.0.0.1:", fit_->port()), "--api-key-file",
       key.string(), "--weights", (dir_ / "w.json").string(), "--garment", garment_.id(),
       "--avatar", (SmallCatalogue() / "pop" / "avatar-00003.obj").string(), "--raw", "--out",
       (dir_ / "remote.obj").string()});
  ASSERT_EQ(remote.exit_code, 0) << remote.err;
  auto from_remote = core::ReadGarmentObj(dir_ / "remote.obj");
  ASSERT_TRUE(from_remote.ok());
  EXPECT_LT((from_remote->mesh.positions - expected->mesh.positions).cwiseAbs().maxCoeff(), 1e-5);

  // An outfit carries the mesh to every item.
  v1::FitOutfitRequest outfit_request;
  *outfit_request.mutable_weights() = projection.weights();
  *outfit_request.mutable_body() = own.avatar();
  outfit_request.set_encoding(v1::POSITIONS_ENCODING_RAW);
  outfit_request.add_items()->set_garment_id(garment_.id());
  v1::FitOutfitResponse outfit;
  ASSERT_TRUE(stub_->FitOutfit(Call(TestKeys::kCustomer).get(), outfit_request, &outfit).ok());
  ASSERT_EQ(outfit.garments_size(), 1);
  EXPECT_THAT(outfit.garments(0).positions().raw().xyz(),
              ::testing::ElementsAreArray(on_own.positions().raw().xyz()));
}

TEST_F(FitServiceTest, AnOwnMeshThatIsNotTheWeightsBodyIsRefused) {
  const v1::AvatarProjection projection = Project(3);
  v1::FitGarmentRequest request = FitRequest(projection.weights());
  // Another person's mesh: centimetres from the body of these weights.
  *request.mutable_body() = AvatarRequest(5, /*draco=*/true).avatar();
  v1::FittedGarment fitted;
  grpc::Status status = stub_->FitGarment(Call(TestKeys::kCustomer).get(), request, &fitted);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("from the body of the weights"));
  v1::Avatar broken = AvatarRequest(3, /*draco=*/false).avatar();
  broken.mutable_positions()->mutable_raw()->set_xyz(7, std::numeric_limits<float>::infinity());
  *request.mutable_body() = broken;
  status = stub_->FitGarment(Call(TestKeys::kCustomer).get(), request, &fitted);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("non-finite"));
  broken.mutable_positions()->mutable_raw()->mutable_xyz()->RemoveLast();
  *request.mutable_body() = broken;
  EXPECT_EQ(FitCode(request), grpc::StatusCode::INVALID_ARGUMENT);
  v1::FitOutfitRequest outfit_request;
  *outfit_request.mutable_weights() = projection.weights();
  *outfit_request.mutable_body() = AvatarRequest(5, /*draco=*/true).avatar();
  outfit_request.add_items()->set_garment_id(garment_.id());
  v1::FitOutfitResponse outfit;
  EXPECT_EQ(stub_->FitOutfit(Call(TestKeys::kCustomer).get(), outfit_request, &outfit)
                .error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
}

TEST_F(FitServiceTest, AnOutfitFitsEverySizeWithAClothingBasis) {
  const v1::AvatarProjection projection = Project(2);
  v1::FitOutfitRequest request;
  *request.mutable_weights() = projection.weights();
  request.add_items()->set_garment_id(garment_.id());  // Every size: only M is built.
  v1::FitOutfitResponse outfit;
  ASSERT_TRUE(stub_->FitOutfit(Call(TestKeys::kCustomer).get(), request, &outfit).ok());
  ASSERT_EQ(outfit.garments_size(), 1);
  EXPECT_EQ(outfit.garments(0).size(), "M");
  request.mutable_items(0)->set_size("XL");  // Named, but not built.
  EXPECT_EQ(stub_->FitOutfit(Call(TestKeys::kCustomer).get(), request, &outfit).error_code(),
            grpc::StatusCode::NOT_FOUND);
}

TEST_F(FitServiceTest, SizeAdviceJudgesEveryBuiltSizeOnTheBodyOfTheWeights) {
  v1::ProjectAvatarRequest project = AvatarRequest(2, false);
  project.set_with_body(true);
  v1::AvatarProjection projection;
  ASSERT_TRUE(stub_->ProjectAvatar(Call(TestKeys::kCustomer).get(), project, &projection).ok());
  auto body = proto::AvatarPositions(projection.body());
  ASSERT_TRUE(body.ok()) << body.status();
  EXPECT_EQ(body->rows(), body::kBodyVertexCount);

  v1::ShopGarments shop;
  ASSERT_TRUE(stub_->ListShopGarments(Call(TestKeys::kCustomer).get(), {}, &shop).ok());
  ASSERT_EQ(shop.garments_size(), 1);
  EXPECT_EQ(shop.garments(0).garment_id(), garment_.id());
  EXPECT_EQ(shop.garments(0).population(), "women");
  EXPECT_THAT(shop.garments(0).sizes(), ::testing::ElementsAre("M"));  // XL is not built.
  v1::GetBodyTopologyRequest topology_request;
  topology_request.set_population("women");
  v1::BodyTopology topology;
  ASSERT_TRUE(
      stub_->GetBodyTopology(Call(TestKeys::kCustomer).get(), topology_request, &topology).ok());
  EXPECT_EQ(topology.faces().vertex_count(), static_cast<uint32_t>(body::kBodyVertexCount));
  EXPECT_GT(topology.faces().face_sizes_size(), 0);

  v1::AdviseSizeRequest request;
  *request.mutable_weights() = projection.weights();
  request.set_garment_id(garment_.id());
  v1::SizeAdvice advice;
  const grpc::Status status = stub_->AdviseSize(Call(TestKeys::kCustomer).get(), request, &advice);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(advice.recommended_size(), "M");
  EXPECT_GT(advice.confidence(), 0.0);
  EXPECT_FALSE(advice.out_of_distribution());  // A training body.
  ASSERT_EQ(advice.sizes_size(), 1);
  const v1::SizeFit& m = advice.sizes(0);
  EXPECT_EQ(m.ease_mm_size(), garment_.template_mesh().vertex_count());
  EXPECT_EQ(m.stretch_pct_size(), garment_.template_mesh().vertex_count());
  std::vector<std::string> regions;
  for (const v1::RegionFit& region : m.regions()) {
    regions.push_back(region.region());
    EXPECT_NEAR(region.ease_cm(), region.garment_cm() - region.body_cm(), 1e-9);
  }
  // A sports top over leggings: the midriff between them is bare, so no waist girth.
  EXPECT_THAT(regions, ::testing::IsSupersetOf({"bust", "hip", "thigh"}));
  EXPECT_THAT(regions, ::testing::Not(::testing::Contains("waist")));
  EXPECT_THAT(m.summary(), ::testing::StartsWith("M: "));

  request.add_sizes("XL");
  EXPECT_EQ(stub_->AdviseSize(Call(TestKeys::kCustomer).get(), request, &advice).error_code(),
            grpc::StatusCode::NOT_FOUND);
  request.clear_sizes();
  request.mutable_weights()->set_basis_id("another-basis");
  EXPECT_EQ(stub_->AdviseSize(Call(TestKeys::kCustomer).get(), request, &advice).error_code(),
            grpc::StatusCode::FAILED_PRECONDITION);
}

TEST_F(FitServiceTest, ANewlyPublishedVersionServesWithoutARestart) {
  const v1::AvatarProjection projection = Project(1);
  v1::FittedGarment first;
  ASSERT_TRUE(stub_->FitGarment(Call(TestKeys::kCustomer).get(), FitRequest(projection.weights()),
                                &first)
                  .ok());
  const storage::ClothingBasisKey key{"acme", garment_.id(), "M", garment_.avatar_basis_id(),
                                      "linear"};
  v1::ClothingBasis moved;
  ASSERT_TRUE(moved.ParseFromString(coordinator_->store().GetCurrentClothingBasis(key)->bytes));
  moved.set_id("moved-by-a-rebuild");
  ASSERT_TRUE(coordinator_->store()
                  .PublishClothingBasis(key, moved.id(), proto::SerializeDeterministically(moved))
                  .ok());
  clock_.Advance(absl::Seconds(2));  // Past the catalogue's refresh.
  v1::FittedGarment second;
  ASSERT_TRUE(stub_->FitGarment(Call(TestKeys::kCustomer).get(), FitRequest(projection.weights()),
                                &second)
                  .ok());
  EXPECT_EQ(second.clothing_basis_version(), 2u);
  EXPECT_EQ(second.clothing_basis_id(), "moved-by-a-rebuild");
}

TEST_F(FitServiceTest, AnUnnamedMethodServesTheKernelBasisOnceItIsPublished) {
  const v1::AvatarProjection projection = Project(1);
  v1::FittedGarment linear;
  ASSERT_TRUE(stub_->FitGarment(Call(TestKeys::kCustomer).get(), FitRequest(projection.weights()),
                                &linear)
                  .ok());
  EXPECT_EQ(linear.method(), "linear");
  // A kernel basis whose correction has no outputs fits exactly as the linear one.
  storage::ClothingBasisKey key{"acme", garment_.id(), "M", garment_.avatar_basis_id(), "linear"};
  v1::ClothingBasis kernel;
  ASSERT_TRUE(kernel.ParseFromString(coordinator_->store().GetCurrentClothingBasis(key)->bytes));
  kernel.set_method("kernel");
  kernel.set_id("kernel-basis");
  kernel.mutable_kernel()->set_length_scale(1);
  kernel.mutable_kernel()->mutable_input_scale()->Resize(
      static_cast<int>(kernel.component_count()), 1.0f);
  key.method = "kernel";
  ASSERT_TRUE(coordinator_->store()
                  .PublishClothingBasis(key, kernel.id(), proto::SerializeDeterministically(kernel))
                  .ok());
  clock_.Advance(absl::Seconds(2));
  v1::FittedGarment served;
  ASSERT_TRUE(stub_->FitGarment(Call(TestKeys::kCustomer).get(), FitRequest(projection.weights()),
                                &served)
                  .ok());
  EXPECT_EQ(served.method(), "kernel");
  EXPECT_EQ(served.clothing_basis_id(), "kernel-basis");
  EXPECT_EQ(served.positions().SerializeAsString(), linear.positions().SerializeAsString());
  v1::FitGarmentRequest named = FitRequest(projection.weights());
  named.set_method("linear");
  v1::FittedGarment asked;
  ASSERT_TRUE(stub_->FitGarment(Call(TestKeys::kCustomer).get(), named, &asked).ok());
  EXPECT_EQ(asked.method(), "linear");
}

TEST_F(FitServiceTest, KeysTenantsAndRolesAreEnforced) {
  const v1::AvatarProjection projection = Project(1);
  const v1::FitGarmentRequest request = FitRequest(projection.weights());
  EXPECT_EQ(FitCode(request, ""), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(FitCode(request, "fb_wrong"), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(FitCode(request, TestKeys::kWorker), grpc::StatusCode::PERMISSION_DENIED);
  EXPECT_EQ(FitCode(request, TestKeys::kRival), grpc::StatusCode::PERMISSION_DENIED);
  // Another tenant's garment does not exist for the rival's customers.
  EXPECT_EQ(FitCode(request, TestKeys::kRivalCustomer), grpc::StatusCode::NOT_FOUND);
  v1::GetGarmentTopologyRequest topology;
  topology.set_garment_id(garment_.id());
  v1::GarmentTopology ignored;
  EXPECT_EQ(stub_->GetGarmentTopology(Call(TestKeys::kRivalCustomer).get(), topology, &ignored)
                .error_code(),
            grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(FitCode(request, TestKeys::kAdmin), grpc::StatusCode::OK);
  // A customer key cannot ingest: nothing is written.
  Clients clients(absl::StrCat("127.0.0.1:", coordinator_->port()));
  v1::UploadGarmentRequest upload;
  upload.set_avatar_basis_id(garment_.avatar_basis_id());
  upload.add_sizes("M");
  upload.mutable_obj()->set_name("g.obj");
  upload.mutable_obj()->set_content("v 0 0 0\n");
  v1::UploadGarmentResponse uploaded;
  EXPECT_EQ(clients.catalog->UploadGarment(Call(TestKeys::kCustomer).get(), upload, &uploaded)
                .error_code(),
            grpc::StatusCode::PERMISSION_DENIED);
  EXPECT_EQ(*coordinator_->store().ListGarmentIds("acme"), std::vector<std::string>{garment_.id()});
}

TEST_F(FitServiceTest, BadInputGetsClearCodesWhileOthersAreServed) {
  const v1::AvatarProjection projection = Project(1);
  v1::FitGarmentRequest request = FitRequest(projection.weights());
  std::atomic<bool> stop{false};
  std::atomic<int> served{0}, failed{0};
  std::thread other([&] {
    while (!stop) {
      (FitCode(FitRequest(projection.weights())) == grpc::StatusCode::OK ? served : failed)++;
    }
  });

  v1::ProjectAvatarRequest wrong_count = AvatarRequest(1, false);
  wrong_count.mutable_avatar()->mutable_positions()->mutable_raw()->mutable_xyz()->RemoveLast();
  v1::AvatarProjection ignored;
  EXPECT_EQ(stub_->ProjectAvatar(Call(TestKeys::kCustomer).get(), wrong_count, &ignored)
                .error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
  v1::ProjectAvatarRequest nan = AvatarRequest(1, false);
  nan.mutable_avatar()->mutable_positions()->mutable_raw()->set_xyz(7, std::nanf(""));
  EXPECT_EQ(stub_->ProjectAvatar(Call(TestKeys::kCustomer).get(), nan, &ignored).error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
  v1::ProjectAvatarRequest inf = AvatarRequest(1, false);
  inf.mutable_avatar()->mutable_positions()->mutable_raw()->set_xyz(
      11, std::numeric_limits<float>::infinity());
  EXPECT_EQ(stub_->ProjectAvatar(Call(TestKeys::kCustomer).get(), inf, &ignored).error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
  v1::ProjectAvatarRequest truncated = AvatarRequest(1, true);
  std::string* draco = truncated.mutable_avatar()->mutable_positions()->mutable_draco()
                           ->mutable_data();
  draco->resize(draco->size() / 2);
  const grpc::Status cut =
      stub_->ProjectAvatar(Call(TestKeys::kCustomer).get(), truncated, &ignored);
  EXPECT_EQ(cut.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(cut.error_message(), HasSubstr("Draco"));
  v1::ProjectAvatarRequest oversize = AvatarRequest(1, false);
  oversize.mutable_avatar()->mutable_positions()->mutable_raw()->mutable_xyz()->Resize(
      2 << 20, 0.5f);
  EXPECT_EQ(stub_->ProjectAvatar(Call(TestKeys::kCustomer).get(), oversize, &ignored)
                .error_code(),
            grpc::StatusCode::RESOURCE_EXHAUSTED);

  v1::FitGarmentRequest unknown_garment = request;
  unknown_garment.set_garment_id("no-such-garment");
  EXPECT_EQ(FitCode(unknown_garment), grpc::StatusCode::NOT_FOUND);
  v1::FitGarmentRequest unknown_size = request;
  unknown_size.set_size("XXXL");
  EXPECT_EQ(FitCode(unknown_size), grpc::StatusCode::NOT_FOUND);
  v1::FitGarmentRequest short_weights = request;
  short_weights.mutable_weights()->mutable_weights()->RemoveLast();
  EXPECT_EQ(FitCode(short_weights), grpc::StatusCode::INVALID_ARGUMENT);
  v1::FitGarmentRequest nan_weights = request;
  nan_weights.mutable_weights()->set_weights(0, std::nan(""));
  EXPECT_EQ(FitCode(nan_weights), grpc::StatusCode::INVALID_ARGUMENT);
  v1::FitGarmentRequest inf_weights = request;
  inf_weights.mutable_weights()->set_weights(1, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(FitCode(inf_weights), grpc::StatusCode::INVALID_ARGUMENT);
  v1::FitOutfitRequest huge_outfit;
  *huge_outfit.mutable_weights() = projection.weights();
  for (int i = 0; i < 65; ++i) huge_outfit.add_items()->set_garment_id(garment_.id());
  v1::FitOutfitResponse outfit;
  const grpc::Status too_many =
      stub_->FitOutfit(Call(TestKeys::kCustomer).get(), huge_outfit, &outfit);
  EXPECT_EQ(too_many.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(too_many.error_message(), HasSubstr("at most 64"));
  v1::FitGarmentRequest old_basis = request;
  old_basis.mutable_weights()->set_basis_id("an-older-basis");
  v1::FittedGarment fitted;
  const grpc::Status refused =
      stub_->FitGarment(Call(TestKeys::kCustomer).get(), old_basis, &fitted);
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(refused.error_message(), HasSubstr(garment_.avatar_basis_id()));

  stop = true;
  other.join();
  EXPECT_GT(served.load(), 0);
  EXPECT_EQ(failed.load(), 0);
}

TEST_F(FitServiceTest, AvatarFromMeasurementsMakesABodyThatMeasuresAsGiven) {
  const v1::TypedMeasurements given = MeasurementsOf(3);
  v1::AvatarFromMeasurementsResponse made;
  const grpc::Status status = FromMeasurements(given, &made);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(made.weights().basis_id(), garment_.avatar_basis_id());
  EXPECT_EQ(made.weights().weights_size(), static_cast<int>(SmallBasis().component_count()));
  ASSERT_TRUE(made.avatar().positions().has_draco());
  auto positions = proto::AvatarPositions(made.avatar());
  ASSERT_TRUE(positions.ok()) << positions.status();
  EXPECT_EQ(positions->rows(), body::kBodyVertexCount);

  std::vector<std::string> names;
  for (const v1::MeasurementResidual& residual : made.residuals()) names.push_back(residual.name());
  EXPECT_EQ(names, (std::vector<std::string>{"stature", "weight", "bust_girth", "waist_girth",
                                             "hip_girth"}));
  ASSERT_EQ(made.residuals_size(), 5);
  const v1::MeasurementResidual& stature = made.residuals(0);
  EXPECT_DOUBLE_EQ(stature.given(), given.stature_cm());
  EXPECT_NEAR(stature.reached(), given.stature_cm(), 1.0);
  EXPECT_DOUBLE_EQ(made.residuals(1).given(), given.weight_kg());
  EXPECT_EQ(made.out_of_distribution(), made.reasons_size() > 0);

  // The avatar on the wire is the body the residuals describe, within Draco's 0.4 mm.
  auto faces = pipeline::ReadAvatarObj(SmallCatalogue() / "pop" / "avatar-00003.obj");
  ASSERT_TRUE(faces.ok());
  core::Mesh body = *std::move(faces);
  body.positions = *positions;
  auto measured = body::MeasureBody(body);
  ASSERT_TRUE(measured.ok()) << measured.status();
  EXPECT_NEAR(100 * (*measured)[static_cast<int>(body::Measurement::kStature)], stature.reached(),
              0.1);

  // Raw positions on request; the same request gives the same bytes.
  v1::AvatarFromMeasurementsResponse raw;
  ASSERT_TRUE(FromMeasurements(given, &raw, "women", v1::POSITIONS_ENCODING_RAW).ok());
  EXPECT_TRUE(raw.avatar().positions().has_raw());
  v1::AvatarFromMeasurementsResponse again;
  ASSERT_TRUE(FromMeasurements(given, &again).ok());
  EXPECT_EQ(proto::SerializeDeterministically(again), proto::SerializeDeterministically(made));

  // The weights fit the tenant's garments like projected ones.
  v1::FittedGarment fitted;
  const grpc::Status fit =
      stub_->FitGarment(Call(TestKeys::kCustomer).get(), FitRequest(made.weights()), &fitted);
  EXPECT_TRUE(fit.ok()) << fit.error_message();
}

TEST_F(FitServiceTest, MeasurementsNoBodyOfThePopulationHasAreFlaggedNotRefused) {
  v1::TypedMeasurements given;
  given.set_stature_cm(150);
  given.set_hip_girth_cm(160);
  v1::AvatarFromMeasurementsResponse made;
  const grpc::Status status = FromMeasurements(given, &made);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_TRUE(made.out_of_distribution());
  EXPECT_GT(made.reasons_size(), 0);
  EXPECT_EQ(made.residuals_size(), 2);
  auto positions = proto::AvatarPositions(made.avatar());
  ASSERT_TRUE(positions.ok()) << positions.status();
  EXPECT_EQ(positions->rows(), body::kBodyVertexCount);
}

TEST_F(FitServiceTest, BadMeasurementsAreInvalidArgumentNamingTheField) {
  const v1::TypedMeasurements valid = MeasurementsOf(1);
  v1::TypedMeasurements no_stature = valid;
  no_stature.clear_stature_cm();
  v1::TypedMeasurements nan_stature = valid;
  nan_stature.set_stature_cm(std::nan(""));
  v1::TypedMeasurements tiny = valid;
  tiny.set_stature_cm(40);
  v1::TypedMeasurements negative_waist = valid;
  negative_waist.set_waist_girth_cm(-70);
  const std::vector<std::pair<v1::TypedMeasurements, std::string>> cases = {
      {v1::TypedMeasurements(), "stature_cm"},
      {no_stature, "stature_cm"},
      {nan_stature, "stature_cm"},
      {tiny, "stature_cm"},
      {negative_waist, "waist_girth_cm"},
  };
  for (const auto& [measurements, field] : cases) {
    v1::AvatarFromMeasurementsResponse ignored;
    const grpc::Status status = FromMeasurements(measurements, &ignored);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << field;
    EXPECT_THAT(status.error_message(), HasSubstr(field));
  }
  v1::AvatarFromMeasurementsResponse ignored;
  EXPECT_EQ(FromMeasurements(valid, &ignored, "giants").error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(FromMeasurements(valid, &ignored, "").error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
  // Another tenant's basis does not exist for the rival's customers.
  EXPECT_EQ(FromMeasurements(valid, &ignored, "women", v1::POSITIONS_ENCODING_DRACO,
                             TestKeys::kRivalCustomer)
                .error_code(),
            grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(FromMeasurements(valid, &ignored, "women", v1::POSITIONS_ENCODING_DRACO,
                             TestKeys::kWorker)
                .error_code(),
            grpc::StatusCode::PERMISSION_DENIED);
}

TEST_F(FitServiceTest, CustomerAdviseSaysWhichSizeToBuy) {
  const v1::AvatarProjection projection = Project(2);
  const std::filesystem::path key = dir_ / "customer.key";
  ASSERT_TRUE(core::WriteFileAtomically(key, absl::StrCat(TestKeys::kCustomer, "\n")).ok());
  ASSERT_TRUE(core::WriteFileAtomically(dir_ / "w.json", proto::ToJson(projection.weights())).ok());
  const std::string server = absl::StrCat("127.0.0.1:", fit_->port());
  const Result run = RunFitbase({"customer", "advise", "--server", server, "--api-key-file",
                                 key.string(), "--weights", (dir_ / "w.json").string(),
                                 "--garment", garment_.id(), "--out",
                                 (dir_ / "advice.json").string()});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("We recommend M"));
  EXPECT_THAT(run.out, HasSubstr("bust"));
  v1::SizeAdvice advice;
  ASSERT_TRUE(proto::ParseJson(*core::ReadFileToString(dir_ / "advice.json"), &advice).ok());
  EXPECT_EQ(advice.sizes(0).ease_mm_size(), garment_.template_mesh().vertex_count());
  const Result bad = RunFitbase({"customer", "advise", "--server", server, "--api-key-file",
                                 key.string(), "--weights", (dir_ / "w.json").string(),
                                 "--garment", "no-such-garment"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_THAT(bad.err, HasSubstr("no-such-garment"));
}

TEST_F(FitServiceTest, CustomerFromMeasurementsWritesTheAvatarAndItsWeights) {
  const v1::TypedMeasurements given = MeasurementsOf(2);
  const std::filesystem::path key = dir_ / "customer.key";
  ASSERT_TRUE(core::WriteFileAtomically(key, absl::StrCat(TestKeys::kCustomer, "\n")).ok());
  const std::filesystem::path json = dir_ / "m.json";
  ASSERT_TRUE(core::WriteFileAtomically(
                  json, absl::StrFormat("{\"stature_cm\": %.1f, \"weight_kg\": %.1f, "
                                        "\"hip_girth_cm\": %.1f}\n",
                                        given.stature_cm(), given.weight_kg(),
                                        given.hip_girth_cm()))
                  .ok());
  const std::string server = absl::StrCat("127.0.0.1:", fit_->port());
  const std::vector<std::string> call = {"customer", "from-measurements", "--server", server,
                                         "--api-key-file", key.string(), "--population", "women"};
  std::vector<std::string> args = call;
  args.insert(args.end(), {"--measurements", json.string(), "--out", (dir_ / "a.obj").string(),
                           "--weights", (dir_ / "w.json").string()});
  const Result run = RunFitbase(args);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr(absl::StrFormat("stature %.1f cm ->", given.stature_cm())));
  EXPECT_THAT(run.out, HasSubstr("hip_girth"));

  auto avatar = pipeline::ReadAvatarObj(dir_ / "a.obj");
  ASSERT_TRUE(avatar.ok()) << avatar.status();
  auto population = pipeline::ReadAvatarObj(SmallCatalogue() / "pop" / "avatar-00002.obj");
  ASSERT_TRUE(population.ok());
  EXPECT_EQ(avatar->faces, population->faces);
  auto weights_json = core::ReadFileToString(dir_ / "w.json");
  ASSERT_TRUE(weights_json.ok());
  v1::AvatarWeights weights;
  ASSERT_TRUE(proto::ParseJson(*weights_json, &weights).ok()) << *weights_json;
  v1::TypedMeasurements sent;
  sent.set_stature_cm(given.stature_cm());
  sent.set_weight_kg(given.weight_kg());
  sent.set_hip_girth_cm(given.hip_girth_cm());
  v1::AvatarFromMeasurementsResponse made;
  ASSERT_TRUE(FromMeasurements(sent, &made).ok());
  EXPECT_EQ(proto::SerializeDeterministically(weights),
            proto::SerializeDeterministically(made.weights()));

  // A misspelt key is refused, not dropped.
  ASSERT_TRUE(core::WriteFileAtomically(json, "{\"statue_cm\": 170}\n").ok());
  args = call;
  args.insert(args.end(), {"--measurements", json.string(), "--out", (dir_ / "b.obj").string()});
  const Result misspelt = RunFitbase(args);
  EXPECT_NE(misspelt.exit_code, 0);
  EXPECT_THAT(misspelt.err, HasSubstr("statue_cm"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "b.obj"));
}

}  // namespace
}  // namespace fitbase
