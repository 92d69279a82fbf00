// End-to-end tests of `fitbase garment import` and `fitbase drape` on a shared garment.
#include <string>

#include "absl/strings/str_cat.h"
#include "core/garment_obj.h"
#include "fitbase/v1/garment.pb.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "proto/json_codec.h"
#include "proto/message_file.h"
#include "tests/cli_runner.h"
#include "workers/drape.h"

namespace fitbase {
namespace {

using ::testing::HasSubstr;

constexpr char kGarment[] = "female_sportsuit01";

class GarmentCliTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(Scratch("garment"));
    ASSERT_EQ(RunFitbase({"population", "--preset", "women", "--count", "8", "--seed", "5",
                          "--out", (*dir_ / "pop").string()})
                  .exit_code,
              0);
    ASSERT_EQ(RunFitbase({"basis", "build", "--population", (*dir_ / "pop").string(),
                          "--components", "3", "--out", (*dir_ / "b.fbb").string()})
                  .exit_code,
              0);
    const Result import = RunFitbase({"garment", "import", "--mhclo", Mhclo().string(), "--basis",
                                      (*dir_ / "b.fbb").string(), "--sizes", "S,M,XL", "--out",
                                      (*dir_ / "g.fbg").string()});
    ASSERT_EQ(import.exit_code, 0) << import.err;
  }
  static void TearDownTestSuite() { delete dir_; }

  static fs::path Mhclo() {
    return core::TestDataDir() / "clothes" / kGarment / (std::string(kGarment) + ".mhclo");
  }
  static fs::path Avatar() { return *dir_ / "pop/avatar-00003.obj"; }

  static Result Drape(const std::string& size, const std::string& name,
                      const std::string& method = "drape") {
    return RunFitbase({"drape", "--garment", (*dir_ / "g.fbg").string(), "--size", size,
                       "--avatar", Avatar().string(), "--method", method, "--out",
                       (*dir_ / (name + ".obj")).string(), "--report",
                       (*dir_ / (name + ".json")).string()});
  }
  static v1::DrapeReport Report(const std::string& name) {
    v1::DrapeReport report;
    EXPECT_TRUE(
        proto::ParseJson(*core::ReadFileToString(*dir_ / (name + ".json")), &report).ok());
    return report;
  }

  static fs::path* dir_;
};

fs::path* GarmentCliTest::dir_ = nullptr;

TEST_F(GarmentCliTest, DrapeKeepsTopologyAndStaysOutsideTheBody) {
  const Result r = Drape("M", "m");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto source = core::ReadGarmentObj(core::TestDataDir() / "clothes" / kGarment /
                                     (std::string(kGarment) + ".obj"));
  auto draped = core::ReadGarmentObj(*dir_ / "m.obj");
  ASSERT_TRUE(source.ok() && draped.ok());
  EXPECT_EQ(draped->mesh.vertex_count(), source->mesh.vertex_count());
  EXPECT_EQ(draped->mesh.faces, source->mesh.faces);
  EXPECT_EQ(draped->face_texcoord_indices, source->face_texcoord_indices);
  const std::string json = *core::ReadFileToString(*dir_ / "m.json");
  for (const char* key : {"penetration_below_0mm", "penetration_below_1mm", "strain_mean",
                          "strain_p99", "strain_max", "stretch_p99", "compression_p99",
                          "converged_max_move_mm", "seconds"}) {
    EXPECT_THAT(json, HasSubstr(std::string("\"") + key + "\"")) << key;
  }
  EXPECT_EQ(Report("m").penetration_below_0mm(), 0.0);
}

TEST_F(GarmentCliTest, HelpStatesTheScheduleADrapeRuns) {
  const Result r = RunFitbase({"drape", "--help"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const workers::DrapeSchedule schedule;
  EXPECT_THAT(r.out,
              HasSubstr(absl::StrCat("mean avatar (default: ", schedule.homotopy_steps, ")")));
  EXPECT_THAT(r.out, HasSubstr(absl::StrCat("target body (default: ", schedule.relax_steps, ")")));
}

TEST_F(GarmentCliTest, RepeatedDrapeGivesIdenticalBytes) {
  ASSERT_EQ(Drape("M", "first").exit_code, 0);
  ASSERT_EQ(Drape("M", "second").exit_code, 0);
  EXPECT_EQ(*core::ReadFileToString(*dir_ / "first.obj"),
            *core::ReadFileToString(*dir_ / "second.obj"));
}

TEST_F(GarmentCliTest, SizeChangesTheDrapeButNotTheGeometricFit) {
  const Result s = Drape("S", "s");
  ASSERT_EQ(s.exit_code, 0);
  EXPECT_THAT(s.out, HasSubstr("ties: the size's girth carried onto this body is"));
  ASSERT_EQ(Drape("XL", "xl").exit_code, 0);
  EXPECT_GT(Report("xl").ease_mean_mm(), Report("s").ease_mean_mm());
  // The smaller size is the tighter on the same body, before the drape.
  EXPECT_GT(Report("s").carried_girth_ratio(), Report("xl").carried_girth_ratio());
  EXPECT_GE(Report("s").tie_factor(), Report("xl").tie_factor());
  ASSERT_EQ(Drape("S", "geo_s", "geometric").exit_code, 0);
  EXPECT_FALSE(Report("geo_s").has_carried_girth_ratio());
  ASSERT_EQ(Drape("XL", "geo_xl", "geometric").exit_code, 0);
  EXPECT_EQ(*core::ReadFileToString(*dir_ / "geo_s.obj"),
            *core::ReadFileToString(*dir_ / "geo_xl.obj"));
}

TEST_F(GarmentCliTest, TurningTheSupportsOffChangesTheDrapeAndIsTheDrapesOnly) {
  // female_sportsuit01's leggings have a waistband, whose elastic --no-supports takes away.
  ASSERT_EQ(Drape("M", "supported").exit_code, 0);
  const std::vector<std::string> args = {
      "drape",         "--garment", (*dir_ / "g.fbg").string(), "--avatar", Avatar().string(),
      "--no-supports", "--out"};
  std::vector<std::string> unsupported = args;
  unsupported.push_back((*dir_ / "unsupported.obj").string());
  const Result r = RunFitbase(unsupported);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("waistband"));
  EXPECT_NE(*core::ReadFileToString(*dir_ / "unsupported.obj"),
            *core::ReadFileToString(*dir_ / "supported.obj"));
  std::vector<std::string> geometric = args;
  geometric.insert(geometric.end(), {(*dir_ / "geo.obj").string(), "--method", "geometric"});
  const Result bad = RunFitbase(geometric);
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_THAT(bad.err,
              HasSubstr("--no-supports, --friction, --cuff-friction and --skin-tie are settings "
                        "of the physics drape only"));
  EXPECT_FALSE(fs::exists(*dir_ / "geo.obj"));
}

TEST_F(GarmentCliTest, FrictionInPlaceOfTheTiesChangesTheDrape) {
  ASSERT_EQ(Drape("M", "tied").exit_code, 0);
  const std::string garment = (*dir_ / "g.fbg").string();
  const Result r = RunFitbase({"drape", "--garment", garment, "--avatar", Avatar().string(),
                               "--friction", "0.8", "--out", (*dir_ / "friction.obj").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("waistband"));
  EXPECT_NE(*core::ReadFileToString(*dir_ / "friction.obj"),
            *core::ReadFileToString(*dir_ / "tied.obj"));
  for (const char* flag : {"--friction", "--cuff-friction"}) {
    for (const char* mu : {"-0.1", "nan", "11"}) {
      const Result bad = RunFitbase({"drape", "--garment", garment, "--avatar", Avatar().string(),
                                     flag, mu, "--out", (*dir_ / "bad.obj").string()});
      EXPECT_NE(bad.exit_code, 0) << flag << " " << mu;
      EXPECT_THAT(bad.err, HasSubstr(flag)) << mu;
    }
  }
  EXPECT_FALSE(fs::exists(*dir_ / "bad.obj"));
}

TEST_F(GarmentCliTest, StifferTiesChangeTheDrape) {
  ASSERT_EQ(Drape("M", "tied").exit_code, 0);
  const std::string garment = (*dir_ / "g.fbg").string();
  const Result r = RunFitbase({"drape", "--garment", garment, "--avatar", Avatar().string(),
                               "--skin-tie", "1e6", "--out", (*dir_ / "stiff.obj").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(*core::ReadFileToString(*dir_ / "stiff.obj"),
            *core::ReadFileToString(*dir_ / "tied.obj"));
  for (const char* tie : {"-1", "nan", "1e8"}) {
    const Result bad = RunFitbase({"drape", "--garment", garment, "--avatar", Avatar().string(),
                                   "--skin-tie", tie, "--out", (*dir_ / "bad.obj").string()});
    EXPECT_NE(bad.exit_code, 0) << tie;
    EXPECT_THAT(bad.err, HasSubstr("--skin-tie")) << tie;
  }
  const Result both =
      RunFitbase({"drape", "--garment", garment, "--avatar", Avatar().string(), "--skin-tie", "1e6",
                  "--friction", "0.8", "--out", (*dir_ / "bad.obj").string()});
  EXPECT_NE(both.exit_code, 0);
  EXPECT_THAT(both.err, HasSubstr("friction takes the ties' place"));
  EXPECT_FALSE(fs::exists(*dir_ / "bad.obj"));
}

TEST_F(GarmentCliTest, ImportsARetailersPlacedObj) {
  // A retailer's garment: an OBJ already placed on the mean avatar, in meters.
  const fs::path dir = Scratch("placed");
  ASSERT_EQ(RunFitbase({"basis", "example", "--basis", (*dir_ / "b.fbb").string(), "--component",
                        "0", "--sigma", "0", "--out", (dir / "mean.obj").string()})
                .exit_code,
            0);
  ASSERT_EQ(RunFitbase({"drape", "--garment", (*dir_ / "g.fbg").string(), "--avatar",
                        (dir / "mean.obj").string(), "--method", "geometric", "--out",
                        (dir / "placed.obj").string()})
                .exit_code,
            0);
  Result r = RunFitbase({"garment", "import", "--obj", (dir / "placed.obj").string(), "--basis",
                         (*dir_ / "b.fbb").string(), "--sizes", "M,L", "--out",
                         (dir / "retail.fbg").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  v1::Garment garment;
  ASSERT_TRUE(proto::ReadMessageFile(dir / "retail.fbg", &garment).ok());
  EXPECT_EQ(garment.source().kind(), "obj");
  EXPECT_EQ(garment.name(), "placed");
  EXPECT_EQ(garment.sizes_size(), 2);
  r = RunFitbase({"drape", "--garment", (dir / "retail.fbg").string(), "--avatar",
                  Avatar().string(), "--method", "geometric", "--out", (dir / "g.obj").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("without a .mhclo binding"));
}

TEST_F(GarmentCliTest, BadInputsAreNamed) {
  Result r = Drape("XXL", "bad");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("no size 'XXL'; its sizes are S, M, XL"));

  const fs::path dir = Scratch("garment_bad");
  core::Mesh small;
  small.positions = core::Positions::Random(50, 3);
  ASSERT_TRUE(core::WriteGarmentObj(dir / "small.obj", {small, {}, {}}).ok());
  r = RunFitbase({"drape", "--garment", (*dir_ / "g.fbg").string(), "--avatar",
                  (dir / "small.obj").string(), "--out", (dir / "x.obj").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("has 50 vertices"));

  // An OBJ with one vertex more than its binding binds.
  const std::string obj =
      *core::ReadFileToString(Mhclo().parent_path() / (std::string(kGarment) + ".obj")) +
      "\nv 0 0 0\n";
  ASSERT_TRUE(core::WriteFileAtomically(dir / (std::string(kGarment) + ".obj"), obj).ok());
  fs::copy_file(Mhclo(), dir / Mhclo().filename());
  r = RunFitbase({"garment", "import", "--mhclo", (dir / Mhclo().filename()).string(), "--basis",
                  (*dir_ / "b.fbb").string(), "--out", (dir / "g.fbg").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("vertices but its binding"));
  EXPECT_FALSE(fs::exists(dir / "g.fbg"));

  r = RunFitbase({"garment", "import", "--mhclo", Mhclo().string(), "--basis",
                  (*dir_ / "b.fbb").string(), "--sizes", "M,Huge", "--out",
                  (dir / "g2.fbg").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("unknown size 'Huge'"));
}

}  // namespace
}  // namespace fitbase
