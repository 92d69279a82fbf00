#include "body/body_measurements.h"

#include <cmath>
#include <numbers>
#include <vector>

#include "body/body_model.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::body {
namespace {

using core::StatusIs;

double Get(const BodyMeasurements& m, Measurement which) { return m[static_cast<int>(which)]; }

// A closed elliptic cylinder along y: `segments` around, capped at both ends, outward faces.
core::Mesh EllipticCylinder(double a, double b, double height, int segments) {
  core::Mesh mesh;
  mesh.positions.resize(2 * segments + 2, 3);
  for (int i = 0; i < segments; ++i) {
    const double t = 2 * std::numbers::pi * i / segments;
    mesh.positions.row(i) << a * std::cos(t), 0, b * std::sin(t);
    mesh.positions.row(segments + i) << a * std::cos(t), height, b * std::sin(t);
  }
  mesh.positions.row(2 * segments) << 0, 0, 0;
  mesh.positions.row(2 * segments + 1) << 0, height, 0;
  auto add = [&](std::vector<int32_t> corners) {
    mesh.faces.sizes.push_back(static_cast<int32_t>(corners.size()));
    mesh.faces.indices.insert(mesh.faces.indices.end(), corners.begin(), corners.end());
  };
  for (int i = 0; i < segments; ++i) {
    const int j = (i + 1) % segments;
    add({i, segments + i, segments + j, j});
    add({2 * segments, i, j});
    add({2 * segments + 1, segments + j, segments + i});
  }
  return mesh;
}

TEST(BodyMeasurementsTest, AnEllipticCylindersSectionHasTheEllipsesPerimeter) {
  const double a = 0.16, b = 0.11;
  const core::Mesh cylinder = EllipticCylinder(a, b, 0.5, 720);
  const PlaneSection section = SectionMesh(cylinder.positions, core::Triangulate(cylinder.faces),
                                           {0, 0.2, 0}, {0, 1, 0});
  ASSERT_EQ(section.loops.size(), 1u);
  // Ramanujan's second approximation, exact to 1e-9 relative at this eccentricity.
  const double h = std::pow((a - b) / (a + b), 2);
  const double perimeter =
      std::numbers::pi * (a + b) * (1 + 3 * h / (10 + std::sqrt(4 - 3 * h)));
  EXPECT_NEAR(ConvexHullPerimeter(section.loops[0]), perimeter, 1e-5);
}

TEST(BodyMeasurementsTest, TheHullBridgesHollows) {
  // A square with a notch cut into one side: the tape spans the notch.
  const std::vector<Eigen::Vector2d> notched = {
      {0, 0}, {1, 0}, {1, 1}, {0.6, 1}, {0.5, 0.5}, {0.4, 1}, {0, 1}};
  EXPECT_NEAR(ConvexHullPerimeter(notched), 4.0, 1e-12);
  EXPECT_EQ(ConvexHullPerimeter(std::vector<Eigen::Vector2d>{{1, 1}}), 0.0);
}

TEST(BodyMeasurementsTest, ATiltedSectionSeparatesLoopsByConnectivity) {
  core::Mesh two = EllipticCylinder(0.05, 0.05, 1.0, 64);
  core::Mesh other = EllipticCylinder(0.05, 0.05, 1.0, 64);
  other.positions.col(0).array() += 0.3;
  core::Positions both(two.positions.rows() * 2, 3);
  both << two.positions, other.positions;
  core::Triangles t1 = core::Triangulate(two.faces);
  core::Triangles t2 = t1.array() + static_cast<int32_t>(two.positions.rows());
  core::Triangles triangles(t1.rows() * 2, 3);
  triangles << t1, t2;
  const PlaneSection section = SectionMesh(both, triangles, {0, 0.5, 0}, {0.2, 1, 0});
  EXPECT_EQ(section.loops.size(), 2u);
}

TEST(BodyMeasurementsTest, ABoxEnclosesItsVolume) {
  core::Mesh box;
  box.positions.resize(8, 3);
  for (int i = 0; i < 8; ++i) {
    box.positions.row(i) << 0.3 * (i & 1), 1.7 * ((i >> 1) & 1), 0.2 * ((i >> 2) & 1);
  }
  // Outward quads of the unit cube's corner numbering (bit 0 x, bit 1 y, bit 2 z).
  box.faces.sizes = {4, 4, 4, 4, 4, 4};
  box.faces.indices = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
  EXPECT_NEAR(EnclosedVolume(box.positions, core::Triangulate(box.faces)), 0.3 * 1.7 * 0.2, 1e-12);
}

TEST(BodyMeasurementsTest, NamesRoundTripAndUnknownNamesAreRefused) {
  for (Measurement m : AllMeasurements()) {
    EXPECT_EQ(*ParseMeasurement(MeasurementName(m)), m);
  }
  EXPECT_THAT(ParseMeasurement("chest").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, "'chest'"));
}

class BodyMeasurementsOnMakeHumanTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto model = BodyModel::Load(core::TestDataDir());
    ASSERT_TRUE(model.ok()) << model.status();
    model_ = new BodyModel(*std::move(model));
  }
  static BodyMeasurements Measure(const BodyParams& params) {
    auto body = model_->BuildBody(params);
    EXPECT_TRUE(body.ok()) << body.status();
    auto measured = MeasureBody(*body);
    EXPECT_TRUE(measured.ok()) << measured.status();
    return *measured;
  }
  static BodyModel* model_;
};
BodyModel* BodyMeasurementsOnMakeHumanTest::model_ = nullptr;

TEST_F(BodyMeasurementsOnMakeHumanTest, TheDefaultWomanAndManMeasureAsAdults) {
  for (double gender : {0.0, 1.0}) {
    const BodyMeasurements m = Measure({.gender = gender});
    SCOPED_TRACE(gender);
    EXPECT_GT(Get(m, Measurement::kStature), 1.5);
    EXPECT_LT(Get(m, Measurement::kStature), 1.9);
    EXPECT_GT(Get(m, Measurement::kWeight), 45);
    EXPECT_LT(Get(m, Measurement::kWeight), 95);
    // Girths in their anatomical order, and limbs shorter than the body.
    EXPECT_GT(Get(m, Measurement::kBustGirth), Get(m, Measurement::kWaistGirth));
    EXPECT_GT(Get(m, Measurement::kHipGirth), Get(m, Measurement::kWaistGirth));
    EXPECT_GT(Get(m, Measurement::kWaistGirth), Get(m, Measurement::kThighGirth));
    EXPECT_GT(Get(m, Measurement::kThighGirth), Get(m, Measurement::kUpperArmGirth));
    EXPECT_GT(Get(m, Measurement::kNeckGirth), 0.25);
    EXPECT_LT(Get(m, Measurement::kNeckGirth), 0.5);
    EXPECT_GT(Get(m, Measurement::kInsideLeg), 0.4 * Get(m, Measurement::kStature));
    EXPECT_LT(Get(m, Measurement::kInsideLeg), 0.55 * Get(m, Measurement::kStature));
    EXPECT_GT(Get(m, Measurement::kArmLength), 0.45);
    EXPECT_LT(Get(m, Measurement::kArmLength), 0.7);
    EXPECT_GT(Get(m, Measurement::kShoulderWidth), 0.28);
    EXPECT_LT(Get(m, Measurement::kShoulderWidth), 0.48);
  }
}

TEST_F(BodyMeasurementsOnMakeHumanTest, TheWaistModifierGrowsTheWaistAndNotTheStature) {
  const BodyParams base{.gender = 0.0};
  BodyParams wider = base;
  wider.modifiers["measure/measure-waist-circ-decr|incr"] = 1.0;
  const BodyMeasurements before = Measure(base);
  const BodyMeasurements after = Measure(wider);
  EXPECT_GT(Get(after, Measurement::kWaistGirth), Get(before, Measurement::kWaistGirth) + 0.02);
  EXPECT_NEAR(Get(after, Measurement::kStature), Get(before, Measurement::kStature), 1e-4);
  EXPECT_GT(Get(after, Measurement::kWeight), Get(before, Measurement::kWeight));
}

TEST_F(BodyMeasurementsOnMakeHumanTest, TallerIsTallerAndTheMeasuresAreDeterministic) {
  const BodyMeasurements short_body = Measure({.gender = 1.0, .height = 0.2});
  const BodyMeasurements tall_body = Measure({.gender = 1.0, .height = 0.8});
  EXPECT_GT(Get(tall_body, Measurement::kStature), Get(short_body, Measurement::kStature) + 0.1);
  EXPECT_GT(Get(tall_body, Measurement::kInsideLeg), Get(short_body, Measurement::kInsideLeg));
  EXPECT_EQ(Measure({.gender = 1.0, .height = 0.8}), tall_body);
}

TEST(BodyMeasurementsTest, BadBodiesAreRefused) {
  core::Mesh body;
  body.positions = core::Positions::Zero(10, 3);
  EXPECT_THAT(MeasureBody(body).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, "13380 vertices"));
  body.positions = core::Positions::Zero(kBodyVertexCount, 3);
  body.positions(5, 1) = std::nan("");
  body.faces.sizes = {3};
  body.faces.indices = {0, 1, 2};
  EXPECT_THAT(MeasureBody(body).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, "non-finite"));
  body.positions(5, 1) = 0;
  EXPECT_THAT(MeasureBody(body).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, "cannot be taken"));
}

}  // namespace
}  // namespace fitbase::body
