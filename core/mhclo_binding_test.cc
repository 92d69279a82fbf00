#include "core/mhclo_binding.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/obj_io.h"
#include "core/test_support.h"
#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

// The vertices of MakeHuman's hm08 mesh, which the shipped bindings reference: body/'s
// kFullVertexCount, which core/ may not include.
constexpr int64_t kHm08VertexCount = 19158;

// Four reference vertices. The scales span 2 units along x over a reference distance of 4
// (sx = 0.5), 3 along y over 1 (sy = 3) and 1 along z over 4 (sz = 0.25).
constexpr char kSmallMhclo[] =
    "# hand-written\n"
    "name little shirt\n"
    "uuid 0000\n"
    "obj_file little.obj  # the garment\n"
    "x_scale 0 1 4.0\n"
    "y_scale 0 2 1\n"
    "z_scale 0 3 4.0\n"
    "z_depth 50\n"
    "verts 0\n"
    "2\n"
    "\n"
    "0 1 2 0.5 0.25 0.25 1 2 -4\n"
    "delete_verts\n"
    "1 - 3\n"
    "0\n";

Positions SmallReference() {
  Positions p(4, 3);
  p << 0, 0, 0,  //
      2, 0, 0,   //
      0, 3, 0,   //
      0, 0, 1;
  return p;
}

TEST(MhcloBindingTest, ParsesHeaderSingleIndexAndWeightedLines) {
  auto binding = ParseMhclo(kSmallMhclo, 4, "little.mhclo");
  ASSERT_TRUE(binding.ok()) << binding.status();
  EXPECT_EQ(binding->name, "little shirt");
  EXPECT_EQ(binding->obj_file, "little.obj");
  // delete_verts' `1 - 3` and `0` are not vertices.
  ASSERT_EQ(binding->vertex_count(), 2);
  EXPECT_EQ(binding->reference_vertices.row(0), Eigen::RowVector3i(2, 2, 2));
  EXPECT_EQ(binding->weights.row(0), Eigen::RowVector3d(1, 0, 0));
  EXPECT_EQ(binding->offsets.row(0), Eigen::RowVector3d(0, 0, 0));
  EXPECT_EQ(binding->reference_vertices.row(1), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(binding->weights.row(1), Eigen::RowVector3d(0.5, 0.25, 0.25));
  EXPECT_EQ(binding->offsets.row(1), Eigen::RowVector3d(1, 2, -4));
  EXPECT_EQ(binding->scales[0].i, 0);
  EXPECT_EQ(binding->scales[0].j, 1);
  EXPECT_EQ(binding->scales[0].reference_distance, 4.0);
  EXPECT_EQ(binding->scales[2].j, 3);
  EXPECT_EQ(binding->scales[2].reference_distance, 4.0);
}

TEST(MhcloBindingTest, AppliesWeightsAndAxisScaledOffsets) {
  auto binding = ParseMhclo(kSmallMhclo, 4, "little.mhclo");
  ASSERT_TRUE(binding.ok()) << binding.status();
  const Positions garment = ApplyMhclo(*binding, SmallReference());
  ASSERT_EQ(garment.rows(), 2);
  EXPECT_EQ(garment.row(0), Eigen::RowVector3d(0, 3, 0));
  // 0.5*(0,0,0) + 0.25*(2,0,0) + 0.25*(0,3,0) + (1*0.5, 2*3, -4*0.25).
  EXPECT_EQ(garment.row(1), Eigen::RowVector3d(1.0, 6.75, -1.0));
}

TEST(MhcloBindingTest, ScaleUsesAbsoluteDistance) {
  auto binding = ParseMhclo(kSmallMhclo, 4, "little.mhclo");
  ASSERT_TRUE(binding.ok()) << binding.status();
  Positions mirrored = SmallReference();
  mirrored.col(0) *= -1.0;
  const Positions garment = ApplyMhclo(*binding, mirrored);
  EXPECT_EQ(garment.row(1), Eigen::RowVector3d(0.0, 6.75, -1.0));
}

TEST(MhcloBindingTest, VertexBlockRunsToEndOfFile) {
  auto binding = ParseMhclo("verts 0\n1\n3\nx_scale 0 1 1\ny_scale 0 1 1\nz_scale 0 1 1\n", 4, "t");
  ASSERT_TRUE(binding.ok()) << binding.status();
  EXPECT_EQ(binding->vertex_count(), 2);
  binding = ParseMhclo("x_scale 0 1 1\ny_scale 0 1 1\nz_scale 0 1 1\nverts 0\n1\n3", 4, "t");
  ASSERT_TRUE(binding.ok()) << binding.status();
  ASSERT_EQ(binding->vertex_count(), 2);
  EXPECT_EQ(binding->reference_vertices(1, 0), 3);
}

TEST(MhcloBindingTest, MalformedInputNamesFileAndLine) {
  const std::string header = "x_scale 0 1 1\ny_scale 0 2 1\nz_scale 0 3 1\nverts 0\n";
  struct Case {
    std::string text;
    const char* expected;
  };
  const std::vector<Case> cases = {
      {header + "0 1\n", "expected 'i j k wi wj wk dx dy dz' or a single index"},
      {header + "0 1 2 1 0 0 0 0\n", "expected 'i j k wi wj wk dx dy dz'"},
      {header + "0 1 2 1 0 0 0 0 0 0\n", "expected 'i j k wi wj wk dx dy dz'"},
      {header + "0 1 x 1 0 0 0 0 0\n", "not an integer"},
      {header + "1.5\n", "not an integer"},
      {header + "0 1 4 1 0 0 0 0 0\n", "outside [0, 4)"},
      {header + "-1\n", "outside [0, 4)"},
      {header + "0 1 2 1 0 w 0 0 0\n", "weight is not a finite number"},
      {header + "0 1 2 1 0 nan 0 0 0\n", "weight is not a finite number"},
      {header + "0 1 2 1 0 0 0 inf 0\n", "offset is not a finite number"},
      {"x_scale 0 1 0\ny_scale 0 2 1\nz_scale 0 3 1\nverts 0\n0\n", "positive finite"},
      {"x_scale 0 1 -2\ny_scale 0 2 1\nz_scale 0 3 1\nverts 0\n0\n", "positive finite"},
      {"x_scale 0 1 nan\ny_scale 0 2 1\nz_scale 0 3 1\nverts 0\n0\n", "positive finite"},
      {"x_scale 0 9 1\ny_scale 0 2 1\nz_scale 0 3 1\nverts 0\n0\n", "outside [0, 4)"},
      {"x_scale 0 1\ny_scale 0 2 1\nz_scale 0 3 1\nverts 0\n0\n", "expected 'x_scale i j"},
      {header + "x_scale 0 1 1\n", "repeated x_scale"},
      {header + "0\nverts 0\n1\n", "a second 'verts' block"},
  };
  for (const Case& c : cases) {
    auto binding = ParseMhclo(c.text, 4, "bad.mhclo");
    ASSERT_FALSE(binding.ok()) << c.text;
    EXPECT_THAT(binding, StatusIs(absl::StatusCode::kInvalidArgument, c.expected)) << c.text;
    EXPECT_THAT(binding, StatusIs(absl::StatusCode::kInvalidArgument, "mhclo bad.mhclo line "));
  }
}

TEST(MhcloBindingTest, MissingSectionsAreErrors) {
  EXPECT_THAT(ParseMhclo("y_scale 0 2 1\nz_scale 0 3 1\nverts 0\n0\n", 4, "bad.mhclo"),
              StatusIs(absl::StatusCode::kInvalidArgument, "mhclo bad.mhclo: no x_scale line"));
  EXPECT_THAT(ParseMhclo("x_scale 0 2 1\ny_scale 0 3 1\nverts 0\n0\n", 4, "bad.mhclo"),
              StatusIs(absl::StatusCode::kInvalidArgument, "no z_scale line"));
  EXPECT_THAT(ParseMhclo("x_scale 0 1 1\ny_scale 0 2 1\nz_scale 0 3 1\n0 1 2 1 0 0 0 0 0\n", 4,
                         "bad.mhclo"),
              StatusIs(absl::StatusCode::kInvalidArgument, "no 'verts' line"));
  EXPECT_THAT(ParseMhclo("x_scale 0 1 1\ny_scale 0 2 1\nz_scale 0 3 1\nverts 0\ndelete_verts\n1\n",
                         4, "bad.mhclo"),
              StatusIs(absl::StatusCode::kInvalidArgument, "no vertex lines"));
}

TEST(MhcloBindingTest, MissingFileIsNotFound) {
  EXPECT_EQ(ReadMhclo(TestDataDir() / "clothes/no-such.mhclo", kHm08VertexCount).status().code(),
            absl::StatusCode::kNotFound);
}

const Positions& BasePositions() {
  static const Positions* const base = [] {
    auto mesh = ReadObj(TestDataDir() / "base.obj");
    if (!mesh.ok()) std::abort();
    return new Positions(std::move(mesh->positions));
  }();
  return *base;
}

TEST(MhcloBindingTest, OutputFollowsTheReferenceUnits) {
  auto binding = ReadMhclo(TestDataDir() / "clothes/male_casualsuit01/male_casualsuit01.mhclo",
                           kHm08VertexCount);
  ASSERT_TRUE(binding.ok()) << binding.status();
  const Positions in_decimeters = ApplyMhclo(*binding, BasePositions());
  const Positions in_meters = ApplyMhclo(*binding, BasePositions() * 0.1);
  EXPECT_LT((in_meters - 0.1 * in_decimeters).cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace fitbase::core
