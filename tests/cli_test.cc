// End-to-end tests of the `fitbase` binary: real processes, real files, real MakeHuman data.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "body/body_model.h"
#include "core/file_util.h"
#include "core/mesh.h"
#include "core/obj_io.h"
#include "core/test_support.h"
#include "tests/cli_runner.h"
#include "fitbase/v1/avatar.pb.h"
#include "fitbase/v1/avatar_basis.pb.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "proto/json_codec.h"
#include "proto/message_file.h"

namespace fitbase {
namespace {

using ::testing::HasSubstr;

namespace fs = std::filesystem;

TEST(CliTest, EveryCommandHasHelp) {
  for (const std::vector<std::string>& command :
       std::vector<std::vector<std::string>>{{"--help"},
                                             {"avatar", "--help"},
                                             {"avatar", "measure", "--help"},
                                             {"population", "--help"},
                                             {"basis", "--help"},
                                             {"basis", "build", "--help"},
                                             {"basis", "info", "--help"},
                                             {"basis", "project", "--help"},
                                             {"basis", "example", "--help"},
                                             {"basis", "eval", "--help"}}) {
    const Result r = RunFitbase(command);
    EXPECT_EQ(r.exit_code, 0) << absl::StrJoin(command, " ");
    EXPECT_THAT(r.out, HasSubstr("Usage")) << absl::StrJoin(command, " ");
  }
}

TEST(CliTest, AvatarMatchesTheBodyModel) {
  const fs::path dir = Scratch("avatar");
  const Result r = RunFitbase({"avatar", "--params", R"({"gender": 0.2, "age_years": 40,
      "modifiers": {"measure/measure-waist-circ-decr|incr": 0.5}})",
                        "--out", (dir / "a.obj").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto written = core::ReadObj(dir / "a.obj");
  ASSERT_TRUE(written.ok()) << written.status();
  auto model = body::BodyModel::Load(core::TestDataDir());
  ASSERT_TRUE(model.ok());
  body::BodyParams params;
  params.gender = 0.2;
  params.age_years = 40;
  params.modifiers["measure/measure-waist-circ-decr|incr"] = 0.5;
  auto expected = model->BuildBody(params);
  ASSERT_TRUE(expected.ok());
  ASSERT_EQ(written->vertex_count(), body::kBodyVertexCount);
  EXPECT_LT((written->positions - expected->positions).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_EQ(written->faces, expected->faces);
}

TEST(CliTest, AvatarMeasureGivesCentimetresAndKilograms) {
  const fs::path dir = Scratch("measure");
  ASSERT_EQ(RunFitbase({"avatar", "--params", R"({"gender": 1})", "--out",
                        (dir / "m.obj").string()}).exit_code, 0);
  const Result r = RunFitbase({"avatar", "measure", (dir / "m.obj").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // MakeHuman's default man: 1.73 m (the mesh's extent) and a plausible adult's girths.
  EXPECT_THAT(r.out, HasSubstr(R"("stature_cm": 173.0)"));
  for (const char* key : {"weight_kg", "bust_girth_cm", "underbust_girth_cm", "waist_girth_cm",
                          "navel_waist_girth_cm", "hip_girth_cm", "thigh_girth_cm",
                          "upper_arm_girth_cm", "neck_girth_cm", "inside_leg_cm",
                          "arm_length_cm", "shoulder_width_cm"}) {
    EXPECT_THAT(r.out, HasSubstr(absl::StrCat("\"", key, "\": "))) << key;
  }
  const Result table = RunFitbase({"avatar", "measure", (dir / "m.obj").string()});
  EXPECT_THAT(table.out, HasSubstr("stature            173.0 cm"));

  ASSERT_TRUE(core::WriteFileAtomically(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").ok());
  const Result bad = RunFitbase({"avatar", "measure", (dir / "bad.obj").string()});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_THAT(bad.err, HasSubstr("bad.obj"));
}

TEST(CliTest, AvatarParamsFromFile) {
  const fs::path dir = Scratch("avatar_file");
  ASSERT_TRUE(core::WriteFileAtomically(dir / "p.json", R"({"weight": 0.9})").ok());
  const Result r = RunFitbase({"avatar", "--params", (dir / "p.json").string(), "--out",
                        (dir / "a.obj").string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "a.obj"));
}

TEST(CliTest, RenderWritesAPngOfTheAvatar) {
  const fs::path dir = Scratch("render");
  ASSERT_EQ(RunFitbase({"avatar", "--params", "{}", "--out", (dir / "a.obj").string()}).exit_code,
            0);
  const Result r = RunFitbase({"render", "--body", (dir / "a.obj").string(), "--height", "200",
                               "--out", (dir / "a.png").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("a.png"));
  const auto png = core::ReadFileToString(dir / "a.png");
  ASSERT_TRUE(png.ok()) << png.status();
  ASSERT_GE(png->size(), 24u);
  EXPECT_EQ(png->substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  const auto be32 = [&](size_t at) {
    uint32_t v = 0;
    for (size_t i = at; i < at + 4; ++i) v = (v << 8) | static_cast<uint8_t>((*png)[i]);
    return v;
  };
  // Front (arms out: about 1 m wide) and side (about 0.3 m deep) views of a 1.7 m tall body.
  EXPECT_GT(be32(16), 150u);
  EXPECT_LT(be32(16), 250u);
  EXPECT_EQ(be32(20), 200u);

  const Result small = RunFitbase({"render", "--body", (dir / "a.obj").string(), "--height", "10",
                                   "--out", (dir / "b.png").string()});
  EXPECT_NE(small.exit_code, 0);
  EXPECT_THAT(small.err, HasSubstr("--height"));
  const Result missing = RunFitbase({"render", "--body", (dir / "none.obj").string(), "--out",
                                     (dir / "b.png").string()});
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_THAT(missing.err, HasSubstr("--body"));
}

TEST(CliTest, RenderSaysHowMuchSkinShowsThroughEachGarment) {
  const fs::path dir = Scratch("render_skin");
  ASSERT_EQ(RunFitbase({"avatar", "--params", "{}", "--out", (dir / "a.obj").string()}).exit_code,
            0);
  const absl::StatusOr<core::Mesh> body = core::ReadObj(dir / "a.obj");
  ASSERT_TRUE(body.ok()) << body.status();
  // A "garment" that is the body moved 5 mm out along its vertex normals covers it everywhere;
  // moved 5 mm in, the skin shows wherever it would be seen.
  const core::Positions normals =
      core::VertexNormals(body->positions, core::Triangulate(body->faces));
  for (const auto& [name, shift] : {std::pair{"out.obj", 0.005}, std::pair{"in.obj", -0.005}}) {
    core::Mesh garment = *body;
    garment.positions += shift * normals;
    ASSERT_TRUE(core::WriteObj(dir / name, garment).ok());
  }
  const Result r = RunFitbase({"render", "--body", (dir / "a.obj").string(), "--garment",
                               (dir / "out.obj").string(), "--garment", (dir / "in.obj").string(),
                               "--out", (dir / "a.png").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("skin through " + (dir / "out.obj").string() + ": 0.00%"));
  // All but the thinnest parts (fingers, ears), where the shift crosses the body.
  const std::string inside = "skin through " + (dir / "in.obj").string() + ": ";
  const size_t at = r.out.find(inside);
  ASSERT_NE(at, std::string::npos) << r.out;
  EXPECT_GT(std::stod(r.out.substr(at + inside.size())), 99.0) << r.out;

  // Judged against the outer one as the reference, the inner one shows the body through it
  // nearly everywhere, and the outer one against itself nowhere.
  const std::string against = "visible skin against " + (dir / "out.obj").string() + ": ";
  const Result sunk = RunFitbase({"render", "--body", (dir / "a.obj").string(), "--garment",
                                  (dir / "in.obj").string(), "--reference-garment",
                                  (dir / "out.obj").string(), "--out", (dir / "b.png").string()});
  ASSERT_EQ(sunk.exit_code, 0) << sunk.err;
  const size_t sunk_at = sunk.out.find(against);
  ASSERT_NE(sunk_at, std::string::npos) << sunk.out;
  EXPECT_GT(std::stod(sunk.out.substr(sunk_at + against.size())), 90.0) << sunk.out;
  EXPECT_TRUE(fs::exists(dir / "b.png"));
  const Result same = RunFitbase({"render", "--body", (dir / "a.obj").string(), "--garment",
                                  (dir / "out.obj").string(), "--reference-garment",
                                  (dir / "out.obj").string(), "--reference-body",
                                  (dir / "a.obj").string(), "--out", (dir / "c.png").string()});
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_THAT(same.out, HasSubstr(against + "0.00%"));

  const Result two = RunFitbase({"render", "--body", (dir / "a.obj").string(), "--garment",
                                 (dir / "in.obj").string(), "--garment", (dir / "out.obj").string(),
                                 "--reference-garment", (dir / "out.obj").string(), "--out",
                                 (dir / "d.png").string()});
  EXPECT_NE(two.exit_code, 0);
  EXPECT_THAT(two.err, HasSubstr("one --garment"));
  const Result lone = RunFitbase({"render", "--body", (dir / "a.obj").string(), "--garment",
                                  (dir / "in.obj").string(), "--reference-body",
                                  (dir / "a.obj").string(), "--out", (dir / "d.png").string()});
  EXPECT_NE(lone.exit_code, 0);
  EXPECT_THAT(lone.err, HasSubstr("--reference-body"));
  const Result missing = RunFitbase({"render", "--body", (dir / "a.obj").string(), "--garment",
                                     (dir / "in.obj").string(), "--reference-garment",
                                     (dir / "none.obj").string(), "--out",
                                     (dir / "d.png").string()});
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_THAT(missing.err, HasSubstr("--reference-garment"));
  EXPECT_FALSE(fs::exists(dir / "d.png"));
}

TEST(CliTest, BadAvatarParamsFailWithTheirName) {
  const fs::path out = Scratch("bad_avatar") / "a.obj";
  struct Case {
    std::string params;
    std::string message;
  };
  for (const Case& c : {Case{R"({"gendr": 1})", "gendr"},
                        Case{R"({"gender": 1.5})", "'gender' is 1.5"},
                        Case{R"({"age_years": 12})", "age_years"},
                        Case{R"({"african": 1})", "ethnic shares"},
                        Case{R"({"modifiers": {"head/head-fat-decr|incr": 1}})", "unknown modifier"},
                        Case{R"({"weight": )", "invalid JSON"},
                        Case{"/no/such/params.json", "cannot open"}}) {
    const Result r = RunFitbase({"avatar", "--params", c.params, "--out", out.string()});
    EXPECT_NE(r.exit_code, 0) << c.params;
    EXPECT_THAT(r.err, HasSubstr(c.message)) << c.params;
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST(CliTest, BadFlagsFail) {
  const fs::path dir = Scratch("bad_flags");
  EXPECT_NE(RunFitbase({"population", "--count", "0", "--out", dir.string()}).exit_code, 0);
  EXPECT_NE(RunFitbase({"population", "--count", "many", "--out", dir.string()}).exit_code, 0);
  const Result preset = RunFitbase({"population", "--preset", "kids", "--count", "2", "--out", dir.string()});
  EXPECT_NE(preset.exit_code, 0);
  EXPECT_THAT(preset.err, HasSubstr("kids"));
  EXPECT_NE(RunFitbase({"basis", "info", (dir / "missing.fbb").string()}).exit_code, 0);
  ASSERT_TRUE(core::WriteFileAtomically(dir / "garbage.fbb", "not a basis").ok());
  const Result garbage = RunFitbase({"basis", "info", (dir / "garbage.fbb").string()});
  EXPECT_NE(garbage.exit_code, 0);
  EXPECT_THAT(garbage.err, HasSubstr("AvatarBasis"));
}

// One population and basis shared by the tests below: the expensive part of the pipeline.
class CliBasisTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(Scratch("basis"));
    const Result pop = RunFitbase({"population", "--preset", "women", "--count", "16", "--seed", "3",
                            "--out", (*dir_ / "pop").string()});
    ASSERT_EQ(pop.exit_code, 0) << pop.err;
    const Result build = RunFitbase({"basis", "build", "--population", (*dir_ / "pop").string(),
                              "--components", "6", "--out", (*dir_ / "b.fbb").string()});
    ASSERT_EQ(build.exit_code, 0) << build.err;
  }
  static void TearDownTestSuite() { delete dir_; }

  static v1::AvatarBasis ReadBasis(const fs::path& path) {
    v1::AvatarBasis basis;
    EXPECT_TRUE(proto::ReadMessageFile(path, &basis).ok());
    return basis;
  }

  static fs::path* dir_;
};

fs::path* CliBasisTest::dir_ = nullptr;

TEST_F(CliBasisTest, PopulationFolderIsComplete) {
  EXPECT_TRUE(fs::exists(*dir_ / "pop/population.json"));
  EXPECT_TRUE(fs::exists(*dir_ / "pop/avatar-00015.obj"));
  EXPECT_FALSE(fs::exists(*dir_ / "pop/avatar-00016.obj"));
  const std::string params = *core::ReadFileToString(*dir_ / "pop/params.jsonl");
  EXPECT_EQ(std::count(params.begin(), params.end(), '\n'), 16);
}

TEST_F(CliBasisTest, SameInputsGiveSameBytesAndId) {
  const Result pop = RunFitbase({"population", "--preset", "women", "--count", "16", "--seed", "3",
                          "--out", (*dir_ / "pop2").string()});
  ASSERT_EQ(pop.exit_code, 0);
  for (const char* file : {"params.jsonl", "population.json", "avatar-00007.obj"}) {
    EXPECT_EQ(*core::ReadFileToString(*dir_ / "pop" / file),
              *core::ReadFileToString(*dir_ / "pop2" / file))
        << file;
  }
  const Result build = RunFitbase({"basis", "build", "--population", (*dir_ / "pop2").string(),
                            "--components", "6", "--out", (*dir_ / "b2.fbb").string()});
  ASSERT_EQ(build.exit_code, 0) << build.err;
  EXPECT_EQ(*core::ReadFileToString(*dir_ / "b.fbb"), *core::ReadFileToString(*dir_ / "b2.fbb"));

  const Result other = RunFitbase({"basis", "build", "--population", (*dir_ / "pop2").string(),
                            "--components", "5", "--out", (*dir_ / "b3.fbb").string()});
  ASSERT_EQ(other.exit_code, 0) << other.err;
  EXPECT_NE(ReadBasis(*dir_ / "b.fbb").id(), ReadBasis(*dir_ / "b3.fbb").id());
}

TEST_F(CliBasisTest, InfoShowsIdAndComponents) {
  const Result r = RunFitbase({"basis", "info", (*dir_ / "b.fbb").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr(ReadBasis(*dir_ / "b.fbb").id()));
  EXPECT_THAT(r.out, HasSubstr("components  6"));
  EXPECT_THAT(r.out, HasSubstr("preset women, seed 3, 16 avatars"));
}

TEST_F(CliBasisTest, ProjectTrainingAvatarAsJson) {
  const Result r = RunFitbase({"basis", "project", "--basis", (*dir_ / "b.fbb").string(), "--avatar",
                        (*dir_ / "pop/avatar-00002.obj").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  v1::AvatarWeights weights;
  ASSERT_TRUE(proto::ParseJson(r.out, &weights).ok()) << r.out;
  EXPECT_EQ(weights.weights_size(), 6);
  EXPECT_EQ(weights.basis_id(), ReadBasis(*dir_ / "b.fbb").id());
  EXPECT_GT(weights.max_error_mm(), weights.mean_error_mm());
  EXPECT_THAT(r.out, HasSubstr("\"mean_error_mm\""));
  EXPECT_THAT(r.out, HasSubstr("\"max_error_mm\""));
  EXPECT_THAT(r.out, HasSubstr("\"weights\""));
}

TEST_F(CliBasisTest, ExampleAtZeroSigmaIsTheMean) {
  const fs::path out = *dir_ / "mean.obj";
  ASSERT_EQ(RunFitbase({"basis", "example", "--basis", (*dir_ / "b.fbb").string(), "--component", "0",
                 "--sigma", "0", "--out", out.string()})
                .exit_code,
            0);
  const Result r = RunFitbase({"basis", "project", "--basis", (*dir_ / "b.fbb").string(), "--avatar",
                        out.string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  v1::AvatarWeights weights;
  ASSERT_TRUE(proto::ParseJson(r.out, &weights).ok());
  for (double w : weights.weights()) EXPECT_NEAR(w, 0.0, 1e-4);

  const Result bad = RunFitbase({"basis", "example", "--basis", (*dir_ / "b.fbb").string(),
                          "--component", "6", "--out", out.string()});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_THAT(bad.err, HasSubstr("components 0 to 5"));
}

TEST_F(CliBasisTest, AvatarFromMeasurementsReproducesAMeasuredBody) {
  const fs::path dir = Scratch("from_measurements");
  const Result measured =
      RunFitbase({"avatar", "measure", "--json", (*dir_ / "pop/avatar-00002.obj").string()});
  ASSERT_EQ(measured.exit_code, 0) << measured.err;
  ASSERT_TRUE(core::WriteFileAtomically(dir / "m.json", measured.out).ok());
  const Result r = RunFitbase({"avatar", "from-measurements", "--basis",
                               (*dir_ / "b.fbb").string(), "--measurements",
                               (dir / "m.json").string(), "--out", (dir / "a.obj").string(),
                               "--weights", (dir / "w.json").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("stature "));
  EXPECT_THAT(r.out, HasSubstr("reached"));
  auto avatar = core::ReadObj(dir / "a.obj");
  ASSERT_TRUE(avatar.ok()) << avatar.status();
  EXPECT_EQ(avatar->vertex_count(), body::kBodyVertexCount);
  // The weights feed `fit --weights` and `basis project`'s consumers alike.
  v1::AvatarWeights weights;
  ASSERT_TRUE(proto::ParseJson(*core::ReadFileToString(dir / "w.json"), &weights).ok());
  EXPECT_FALSE(weights.basis_id().empty());

  struct Case {
    std::string json;
    std::string message;
  };
  for (const Case& c : {Case{R"({"stature_cm": 170, "hight_cm": 3})", "hight_cm"},
                        Case{R"({"weight_kg": 60})", "stature_cm is required"},
                        Case{R"({"stature_cm": 40})", "stature_cm is 40"},
                        Case{R"({})", "no measurements"}}) {
    ASSERT_TRUE(core::WriteFileAtomically(dir / "bad.json", c.json).ok());
    const Result bad = RunFitbase({"avatar", "from-measurements", "--basis",
                                   (*dir_ / "b.fbb").string(), "--measurements",
                                   (dir / "bad.json").string(), "--out",
                                   (dir / "bad.obj").string()});
    EXPECT_NE(bad.exit_code, 0) << c.json;
    EXPECT_THAT(bad.err, HasSubstr(c.message)) << c.json;
    EXPECT_FALSE(fs::exists(dir / "bad.obj"));
  }
}

TEST_F(CliBasisTest, ProjectRejectsBadAvatars) {
  const fs::path dir = Scratch("bad_avatars");
  core::Mesh small;
  small.positions = core::Positions::Random(100, 3);
  ASSERT_TRUE(core::WriteObj(dir / "small.obj", small).ok());
  Result r = RunFitbase({"basis", "project", "--basis", (*dir_ / "b.fbb").string(), "--avatar",
                  (dir / "small.obj").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("has 100 vertices"));

  std::string text = *core::ReadFileToString(*dir_ / "pop/avatar-00000.obj");
  text.replace(text.find("\nv ") + 3, 1, "nan ");
  ASSERT_TRUE(core::WriteFileAtomically(dir / "nan.obj", text).ok());
  r = RunFitbase({"basis", "project", "--basis", (*dir_ / "b.fbb").string(), "--avatar",
           (dir / "nan.obj").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("nan.obj"));
}

TEST_F(CliBasisTest, SelectionRulesAreExclusiveAndChecked) {
  const std::string pop = (*dir_ / "pop").string();
  const std::string out = (*dir_ / "x.fbb").string();
  Result r = RunFitbase({"basis", "build", "--population", pop, "--components", "3", "--variance", "0.9",
                  "--out", out});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("at most one"));
  r = RunFitbase({"basis", "build", "--population", pop, "--components", "40", "--out", out});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("40"));
  r = RunFitbase({"basis", "build", "--population", pop, "--variance", "1.5", "--out", out});
  EXPECT_NE(r.exit_code, 0);
  r = RunFitbase({"basis", "build", "--population", pop, "--max-error-mm", "-1", "--out", out});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace fitbase
