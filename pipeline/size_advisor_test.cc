#include "pipeline/size_advisor.h"

#include <filesystem>
#include <string>

#include "absl/strings/str_cat.h"
#include "body/body_model.h"
#include "body/body_params.h"
#include "core/file_util.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "pipeline/garment_importer.h"
#include "proto/avatar_params_codec.h"
#include "proto/garment_codec.h"
#include "proto/mesh_codec.h"

namespace fitbase::pipeline {
namespace {

// A T-shirt and shorts (1,696 vertices), imported on a two-body basis in three sizes. Its
// template is size M on the mean body: the fitted garment a perfect fit of M would give.
class SizeAdvisorTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    absl::StatusOr<body::BodyModel> model = body::BodyModel::Load(core::TestDataDir());
    ASSERT_TRUE(model.ok()) << model.status();
    v1::AvatarBasis basis;
    basis.set_id("size-advisor-test-basis");
    body::BodyParams params;
    params.gender = 0.9;
    *basis.mutable_population()->add_params() = proto::BodyParamsToProto(params);
    params.weight = 0.7;
    *basis.mutable_population()->add_params() = proto::BodyParamsToProto(params);
    const std::filesystem::path dir = core::TestDataDir() / "clothes" / "male_casualsuit04";
    GarmentImportRequest request;
    request.obj = {"g.obj", core::ReadFileToString(dir / "male_casualsuit04.obj").value_or("")};
    request.mhclo = SourceFile{"g.mhclo",
                               core::ReadFileToString(dir / "male_casualsuit04.mhclo").value_or("")};
    request.sizes = {"S", "M", "L"};
    absl::StatusOr<v1::Garment> garment = ImportGarment(*model, basis, request);
    ASSERT_TRUE(garment.ok()) << garment.status();
    garment_ = new v1::Garment(*std::move(garment));
  }
  static void TearDownTestSuite() { delete garment_; }

  static absl::StatusOr<AdviceBody> MeanBody() {
    absl::StatusOr<core::Mesh> mean = proto::MeshFromProto(garment_->mean_avatar());
    if (!mean.ok()) return mean.status();
    return MeasureAdviceBody(mean->positions.topRows(body::kBodyVertexCount),
                             core::Triangulate(body::BodyFacesOf(mean->faces)));
  }

  static v1::Garment* garment_;
};

v1::Garment* SizeAdvisorTest::garment_ = nullptr;

const clothing::RegionFitValue* Find(const SizeJudgement& judged, clothing::FitRegion region) {
  for (const auto& value : judged.regions) {
    if (value.region == region) return &value;
  }
  return nullptr;
}

TEST_F(SizeAdvisorTest, TheTemplateOnTheMeanBodyIsSizeMUnstretchedWithEaseGrowingBySize) {
  absl::StatusOr<AdviceGarment> garment = PrepareAdviceGarment(*garment_);
  ASSERT_TRUE(garment.ok()) << garment.status();
  EXPECT_EQ(garment->type, clothing::GarmentType::kShirt);
  ASSERT_EQ(garment->size_names, (std::vector<std::string>{"S", "M", "L"}));
  EXPECT_FALSE(garment->sleeve_vertices.empty());
  EXPECT_FALSE(garment->leg_vertices.empty());
  absl::StatusOr<AdviceBody> body = MeanBody();
  ASSERT_TRUE(body.ok()) << body.status();
  absl::StatusOr<core::GarmentMesh> tmpl = proto::GarmentTemplateFromProto(*garment_);
  ASSERT_TRUE(tmpl.ok());

  std::vector<SizeJudgement> judged;
  for (int size = 0; size < 3; ++size) {
    absl::StatusOr<SizeJudgement> one = JudgeSize(*garment, size, *body, tmpl->mesh.positions);
    ASSERT_TRUE(one.ok()) << one.status();
    judged.push_back(*std::move(one));
  }
  const clothing::RegionFitValue* bust_m = Find(judged[1], clothing::FitRegion::kBust);
  ASSERT_NE(bust_m, nullptr);
  // A T-shirt: a shirt's ease at the chest.
  EXPECT_GT(bust_m->ease_cm, 0.0);
  EXPECT_LT(bust_m->ease_cm, 15.0);
  EXPECT_NEAR(bust_m->stretch_pct, 0.0, 1e-6);
  // A grading step is 5% of girth across the length axes; near the armholes those axes turn
  // toward the sleeves, so a chest's loop grows by a little less. S worn at M's shape is
  // stretched by as much.
  const clothing::RegionFitValue* bust_s = Find(judged[0], clothing::FitRegion::kBust);
  const clothing::RegionFitValue* bust_l = Find(judged[2], clothing::FitRegion::kBust);
  ASSERT_NE(bust_s, nullptr);
  ASSERT_NE(bust_l, nullptr);
  EXPECT_NEAR(bust_m->garment_cm / bust_s->garment_cm, 1.045, 0.015);
  EXPECT_NEAR(bust_l->garment_cm / bust_m->garment_cm, 1.045, 0.015);
  EXPECT_NEAR(bust_s->stretch_pct, 4.5, 1.5);
  // Lengths as designed on the mean body are regular.
  for (auto region : {clothing::FitRegion::kGarmentLength, clothing::FitRegion::kSleeveLength}) {
    const clothing::RegionFitValue* length = Find(judged[1], region);
    ASSERT_NE(length, nullptr) << clothing::FitRegionName(region);
    EXPECT_NEAR(length->ease_cm, length->design_ease_cm, 1e-9);
    EXPECT_EQ(length->verdict, clothing::Verdict::kRegular);
  }
  // The fit map: one value per vertex; the template clears the skin nearly everywhere.
  ASSERT_EQ(judged[1].ease_mm.size(), tmpl->mesh.positions.rows());
  EXPECT_GT((judged[1].ease_mm.array() > 0).cast<double>().mean(), 0.95);
  EXPECT_NEAR(judged[0].stretch_pct.mean(), 3.5, 2.0);

  const v1::SizeAdvice advice = AssembleAdvice(*garment, {0, 1, 2}, judged, true);
  ASSERT_EQ(advice.sizes_size(), 3);
  EXPECT_EQ(advice.garment_type(), "shirt");
  EXPECT_FALSE(advice.recommended_size().empty());
  EXPECT_EQ(advice.sizes(1).ease_mm_size(), tmpl->mesh.positions.rows());
  EXPECT_THAT(advice.sizes(0).summary(), ::testing::StartsWith("S: "));
}

TEST_F(SizeAdvisorTest, RejectsAnUnknownTypeAndABadFit) {
  v1::Garment typed = *garment_;
  typed.set_garment_type("tuxedo");
  EXPECT_THAT(PrepareAdviceGarment(typed).status(),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "unknown garment type"));
  absl::StatusOr<AdviceGarment> garment = PrepareAdviceGarment(*garment_);
  ASSERT_TRUE(garment.ok());
  absl::StatusOr<AdviceBody> body = MeanBody();
  ASSERT_TRUE(body.ok());
  EXPECT_FALSE(JudgeSize(*garment, 7, *body, core::Positions(3, 3)).ok());
  core::Positions few = core::Positions::Zero(10, 3);
  EXPECT_THAT(JudgeSize(*garment, 1, *body, few).status(),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "fewer than its faces use"));
}

}  // namespace
}  // namespace fitbase::pipeline
