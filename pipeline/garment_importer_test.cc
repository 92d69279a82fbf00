#include "pipeline/garment_importer.h"

#include <filesystem>
#include <string>

#include "absl/strings/str_cat.h"
#include "body/body_model.h"
#include "body/body_params.h"
#include "core/content_hash.h"
#include "core/file_util.h"
#include "core/garment_obj.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "proto/avatar_params_codec.h"
#include "proto/message_file.h"
#include "workers/cloth_solver.h"

namespace fitbase::pipeline {
namespace {

using core::StatusIs;

// The smallest shipped garment (1,696 vertices), so a whole import takes about a second.
constexpr char kGarment[] = "male_casualsuit04";
constexpr int64_t kGarmentVertexCount = 1696;

std::filesystem::path GarmentFile(absl::string_view extension) {
  return core::TestDataDir() / "clothes" / kGarment / absl::StrCat(kGarment, extension);
}

SourceFile Upload(std::string name, const std::filesystem::path& path) {
  absl::StatusOr<std::string> bytes = core::ReadFileToString(path);
  EXPECT_TRUE(bytes.ok()) << bytes.status();
  return {std::move(name), bytes.value_or("")};
}

class GarmentImporterTest : public ::testing::Test {
 protected:
  // Loading the model reads every target, so the suite shares one.
  static void SetUpTestSuite() {
    absl::StatusOr<body::BodyModel> model = body::BodyModel::Load(core::TestDataDir());
    ASSERT_TRUE(model.ok()) << model.status();
    model_ = new body::BodyModel(*std::move(model));
    // Import needs only the basis's id and training avatars: two bodies, so the mean avatar
    // is no single one of them.
    basis_ = new v1::AvatarBasis;
    basis_->set_id("garment-importer-test-basis");
    body::BodyParams params;
    params.gender = 0.9;
    *basis_->mutable_population()->add_params() = proto::BodyParamsToProto(params);
    params.weight = 0.7;
    *basis_->mutable_population()->add_params() = proto::BodyParamsToProto(params);
  }
  static void TearDownTestSuite() {
    delete model_;
    delete basis_;
  }

  // The shipped garment as a retailer's upload, under other names.
  static GarmentImportRequest UploadedRequest() {
    GarmentImportRequest request;
    request.mhclo = Upload("shirt.mhclo", GarmentFile(".mhclo"));
    request.obj = Upload("shirt.obj", GarmentFile(".obj"));
    request.sizes = {"M", "L"};
    return request;
  }

  static body::BodyModel* model_;
  static v1::AvatarBasis* basis_;
};

body::BodyModel* GarmentImporterTest::model_ = nullptr;
v1::AvatarBasis* GarmentImporterTest::basis_ = nullptr;

TEST_F(GarmentImporterTest, ContentsImportAsTheFilesTheyCameFrom) {
  // A retailer's own L: the garment's rest mesh in meters, 2% wider.
  absl::StatusOr<core::GarmentMesh> l_mesh = core::ReadGarmentObj(GarmentFile(".obj"));
  ASSERT_TRUE(l_mesh.ok()) << l_mesh.status();
  l_mesh->mesh.positions *= body::kMetersPerDataUnit;
  l_mesh->mesh.positions.col(0) *= 1.02;
  const std::filesystem::path l_path = core::ProcessTempDir() / "l.obj";
  ASSERT_TRUE(core::WriteGarmentObj(l_path, *l_mesh).ok());

  GarmentImportPaths paths;
  paths.mhclo = GarmentFile(".mhclo");
  paths.size_meshes["L"] = l_path;
  absl::StatusOr<GarmentImportRequest> read = ReadGarmentImportFiles(paths);
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_EQ(read->obj.name, GarmentFile(".obj").string());
  read->sizes = {"M", "L", "XL"};
  absl::StatusOr<v1::Garment> from_files = ImportGarment(*model_, *basis_, *read);
  ASSERT_TRUE(from_files.ok()) << from_files.status();

  GarmentImportRequest uploaded;
  uploaded.mhclo = Upload(GarmentFile(".mhclo").string(), GarmentFile(".mhclo"));
  uploaded.obj = Upload(GarmentFile(".obj").string(), GarmentFile(".obj"));
  uploaded.size_meshes["L"] = Upload(l_path.string(), l_path);
  uploaded.sizes = {"M", "L", "XL"};
  absl::StatusOr<v1::Garment> from_contents = ImportGarment(*model_, *basis_, uploaded);
  ASSERT_TRUE(from_contents.ok()) << from_contents.status();
  EXPECT_EQ(proto::SerializeDeterministically(*from_contents),
            proto::SerializeDeterministically(*from_files));

  // Provenance and id as import has always recorded them, so re-imports keep their ids.
  EXPECT_EQ(from_contents->name(), kGarment);
  EXPECT_EQ(from_contents->source().kind(), "mhclo");
  EXPECT_EQ(from_contents->source().path(), GarmentFile(".mhclo").string());
  const std::string sha256 =
      core::ContentHash().Add(uploaded.obj.bytes).Add(uploaded.mhclo->bytes).HexDigest();
  EXPECT_EQ(from_contents->source().sha256(), sha256);
  EXPECT_EQ(from_contents->id(), core::ContentHash()
                                     .Add("fitbase-garment-import-v10")
                                     .Add(workers::kSimulatorVersion)
                                     .Add(basis_->id())
                                     .Add(sha256)
                                     .Add("M")
                                     .Add(int64_t{0})
                                     .Add("L")
                                     .Add(uploaded.size_meshes["L"].bytes)
                                     .Add("XL")
                                     .Add(int64_t{2})
                                     .HexDigest());
  // A cache can tell an import is current without redoing it.
  EXPECT_EQ(GarmentImportId(basis_->id(), uploaded).value_or(""), from_contents->id());
  EXPECT_NE(GarmentImportId("another basis", uploaded).value_or(""), from_contents->id());
  EXPECT_EQ(from_contents->template_mesh().vertex_count(), kGarmentVertexCount);
  ASSERT_EQ(from_contents->sizes_size(), 3);
  EXPECT_TRUE(from_contents->sizes(1).has_rest());
}

TEST_F(GarmentImporterTest, DeclaredCuffsAreKeptAndChangeTheId) {
  const GarmentImportRequest plain = UploadedRequest();
  GarmentImportRequest cuffed = plain;
  cuffed.cuffs.set_legs(true);
  absl::StatusOr<v1::Garment> garment = ImportGarment(*model_, *basis_, cuffed);
  ASSERT_TRUE(garment.ok()) << garment.status();
  EXPECT_TRUE(garment->has_cuffs());
  EXPECT_TRUE(garment->cuffs().legs());
  EXPECT_FALSE(garment->cuffs().sleeves());
  EXPECT_EQ(GarmentImportId(basis_->id(), cuffed).value_or(""), garment->id());
  EXPECT_NE(GarmentImportId(basis_->id(), plain).value_or(""), garment->id());
  cuffed.cuffs.set_sleeves(true);
  EXPECT_NE(GarmentImportId(basis_->id(), cuffed).value_or(""), garment->id());
}

TEST(ParseCuffsTest, NamesSleevesLegsOrNone) {
  absl::StatusOr<v1::ElasticCuffs> cuffs = ParseCuffs("legs, sleeves");
  ASSERT_TRUE(cuffs.ok()) << cuffs.status();
  EXPECT_TRUE(cuffs->legs() && cuffs->sleeves());
  cuffs = ParseCuffs("");
  ASSERT_TRUE(cuffs.ok());
  EXPECT_FALSE(cuffs->legs() || cuffs->sleeves());
  EXPECT_TRUE(ParseCuffs("none").ok());
  EXPECT_THAT(ParseCuffs("legs,cuffs"), StatusIs(absl::StatusCode::kInvalidArgument, "'cuffs'"));
  EXPECT_THAT(ParseCuffs("legs,legs"), StatusIs(absl::StatusCode::kInvalidArgument, "twice"));
  EXPECT_THAT(ParseCuffs("none,legs"), StatusIs(absl::StatusCode::kInvalidArgument, "none"));
}

TEST_F(GarmentImporterTest, MalformedObjNamesTheUpload) {
  GarmentImportRequest request = UploadedRequest();
  request.obj = {"retailer upload 12.obj", "v 0 0 0\nv 1 x 0\n"};
  EXPECT_THAT(ImportGarment(*model_, *basis_, request),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       "retailer upload 12.obj line 2: coordinate is not a finite number"));
  request.mhclo.reset();
  EXPECT_THAT(ImportGarment(*model_, *basis_, request),
              StatusIs(absl::StatusCode::kInvalidArgument, "retailer upload 12.obj line 2"));
}

TEST_F(GarmentImporterTest, ObjAndBindingVertexCountsMustAgree) {
  GarmentImportRequest request = UploadedRequest();
  request.obj.bytes += "\nv 0 0 0\n";
  EXPECT_THAT(ImportGarment(*model_, *basis_, request),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       "shirt.obj has 1697 vertices but its binding shirt.mhclo binds 1696"));
}

TEST_F(GarmentImporterTest, SizeMeshesMustFitTheGarmentAndItsSizes) {
  GarmentImportRequest request = UploadedRequest();
  request.size_meshes["L"] = {"shirt-L.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"};
  EXPECT_THAT(ImportGarment(*model_, *basis_, request),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       "size L mesh shirt-L.obj does not have the garment's topology (1696 "
                       "vertices)"));

  request.size_meshes["XL"] = request.size_meshes["L"];
  EXPECT_THAT(ImportGarment(*model_, *basis_, request),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       "size mesh shirt-L.obj is for size XL, not one of the sizes M,L"));

  request.size_meshes.clear();
  request.sizes.clear();
  EXPECT_THAT(ImportGarment(*model_, *basis_, request),
              StatusIs(absl::StatusCode::kInvalidArgument, "at least one size"));
}

TEST(ReadGarmentImportFilesTest, NeedsExactlyOneGarmentFile) {
  GarmentImportPaths paths;
  EXPECT_THAT(ReadGarmentImportFiles(paths),
              StatusIs(absl::StatusCode::kInvalidArgument, "exactly one of --mhclo and --obj"));
  paths.mhclo = GarmentFile(".mhclo");
  paths.obj = GarmentFile(".obj");
  EXPECT_THAT(ReadGarmentImportFiles(paths),
              StatusIs(absl::StatusCode::kInvalidArgument, "exactly one of --mhclo and --obj"));
}

TEST(ReadGarmentImportFilesTest, FindsTheObjItsBindingNames) {
  // A binding whose obj_file names no file beside it, and then none at all.
  absl::StatusOr<std::string> mhclo = core::ReadFileToString(GarmentFile(".mhclo"));
  ASSERT_TRUE(mhclo.ok()) << mhclo.status();
  const std::string obj_line = absl::StrCat("obj_file ", kGarment, ".obj");
  const size_t at = mhclo->find(obj_line);
  ASSERT_NE(at, std::string::npos);
  GarmentImportPaths paths;
  paths.mhclo = core::ProcessTempDir() / "moved.mhclo";
  ASSERT_TRUE(core::WriteFileAtomically(paths.mhclo, *mhclo).ok());
  EXPECT_THAT(ReadGarmentImportFiles(paths),
              StatusIs(absl::StatusCode::kNotFound, absl::StrCat(kGarment, ".obj")));

  mhclo->erase(at, obj_line.size());
  ASSERT_TRUE(core::WriteFileAtomically(paths.mhclo, *mhclo).ok());
  EXPECT_THAT(ReadGarmentImportFiles(paths),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       absl::StrCat(paths.mhclo.string(), " names no obj_file")));
}

}  // namespace
}  // namespace fitbase::pipeline
