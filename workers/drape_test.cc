#include "workers/drape.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "body/body_measurements.h"
#include "body/body_model.h"
#include "core/content_hash.h"
#include "core/triangle_bvh.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "workers/garment_template.h"
#include "workers/test_shapes.h"

namespace fitbase::workers {
namespace {

// A skirt-like tube hanging from an elastic waistband (its top ring) around the waist of an
// hourglass "body": small enough to drape in well under a second, yet with gravity, friction,
// a waistband, collisions and a body that changes size.
class DrapeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    mean_ = Hourglass(0.12, 0.15, 0.3);
    tube_ = Tube(0.145, -0.15, 0.0, 8, 24);
    auto model = BuildClothModel(tube_.positions, tube_.faces, 0.2);
    ASSERT_TRUE(model.ok());
    model_ = *std::move(model);
    for (size_t o = 0; o < model_.openings.size(); ++o) {
      (model_.openings[o].highest_of_piece ? top_index_ : hem_index_) = static_cast<int32_t>(o);
    }
  }

  DrapeInput Input(double target_scale, double rest_scale) const {
    return DrapeInput{.model = &model_,
                      .start = tube_.positions,
                      .edge_rest = rest_scale * PairLengths(tube_.positions, model_.edges),
                      .hinge_rest = HingeAngles(tube_.positions, model_.hinges),
                      .supports = {.waistband_edges = top().edges, .collars = {}, .straps = {}},
                      .regions = {},
                      .mean_body = mean_.positions,
                      .target_body = target_scale * mean_.positions,
                      .body_triangles = core::Triangulate(mean_.faces)};
  }

  // A closed band (its cloth model `model`) in place of the skirt, at `rest_scale` of its own
  // edge lengths, on the unscaled body, with no waistband.
  DrapeInput BandInput(const core::Mesh& band, const ClothModel& model, double rest_scale) const {
    DrapeInput input = Input(1.0, 1.0);
    input.model = &model;
    input.start = band.positions;
    input.edge_rest = rest_scale * PairLengths(band.positions, model.edges);
    input.hinge_rest = HingeAngles(band.positions, model.hinges);
    input.supports = {};
    return input;
  }

  const Opening& top() const { return model_.openings[top_index_]; }

  static std::string Hash(const core::Positions& p) {
    return core::ContentHash()
        .Add(absl::string_view(reinterpret_cast<const char*>(p.data()),
                               sizeof(double) * static_cast<size_t>(p.size())))
        .HexDigest();
  }

  core::Mesh mean_;
  core::Mesh tube_;
  ClothModel model_;
  int32_t top_index_ = 0;   // The tube's top ring, in model_.openings.
  int32_t hem_index_ = -1;  // Its bottom ring, the hem.
};

TEST_F(DrapeTest, RepeatedRunIsBitwiseIdentical) {
  auto a = Drape(Input(1.1, 1.0));
  auto b = Drape(Input(1.1, 1.0));
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(Hash(a->positions), Hash(b->positions));
}

TEST_F(DrapeTest, NothingInsideTheBodyAndTopStaysPut) {
  auto result = Drape(Input(1.15, 1.0));
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->metrics.penetration_below_0mm, 0.0);
  EXPECT_EQ(result->metrics.penetration_below_1mm, 0.0);
  EXPECT_EQ(result->steps, DrapeSchedule{}.homotopy_steps + DrapeSchedule{}.relax_steps);
  // The waistband grips the waist it was put on, on a body 15% larger.
  for (int32_t v : top().vertices) EXPECT_NEAR(result->positions(v, 1), 0.0, 0.01);
}

TEST_F(DrapeTest, TheWaistbandsElasticGripsTheWaist) {
  // The skirt's top is 2.5 cm wider than the waist; an elastic draws it onto the waist
  // (radius 0.12 plus the collision offset), where without one the top ring hangs as cut.
  auto band_radius = [&](const DrapeResult& r) {
    double sum = 0;
    for (int32_t v : top().vertices) sum += std::hypot(r.positions(v, 0), r.positions(v, 2));
    return sum / static_cast<double>(top().vertices.size());
  };
  // The default grip lets a band up to 1 / 0.85 = 18% wider than the waist hang loose, and
  // this one is 18% wider.
  ClothSettings gripping;
  gripping.waistband_grip = 0.75;
  auto with = Drape(Input(1.0, 1.0), gripping);
  auto without = Drape(Input(1.0, 1.0), WithoutSupports({}));
  ASSERT_TRUE(with.ok() && without.ok());
  EXPECT_NEAR(band_radius(*with), 0.12 + ClothSettings{}.collision_offset, 0.002);
  EXPECT_GT(band_radius(*without), 0.14);
}

TEST_F(DrapeTest, ADeclaredCuffGathersTheHemOntoTheBody) {
  // The skirt's hem (y = -0.15, radius 0.145) hangs 6 mm off the hips. Declared a cuff, it
  // carries a waistband's elastic, and is drawn onto them, to the contact offset and no
  // further.
  const int32_t hem = hem_index_;
  ASSERT_GE(hem, 0);
  auto body = core::TriangleBvh::Build(mean_.positions, core::Triangulate(mean_.faces));
  ASSERT_TRUE(body.ok());
  auto hem_gap = [&](const DrapeResult& r) {
    double sum = 0;
    for (int32_t v : model_.openings[hem].vertices) {
      sum += body->Closest(r.positions.row(v).transpose(), 0.1).signed_distance;
    }
    return sum / static_cast<double>(model_.openings[hem].vertices.size());
  };
  DrapeInput cuffed = Input(1.0, 1.0);
  cuffed.supports.cuffs = {hem};
  auto with = Drape(cuffed);
  auto without = Drape(Input(1.0, 1.0));
  ASSERT_TRUE(with.ok() && without.ok());
  EXPECT_EQ(with->metrics.penetration_below_0mm, 0.0);
  EXPECT_GT(hem_gap(*with), 0.0);
  EXPECT_LT(hem_gap(*with), ClothSettings{}.collision_offset + 0.0005);
  EXPECT_GT(hem_gap(*without), 0.005);

  DrapeInput bad = cuffed;
  bad.supports.cuffs = {99};
  EXPECT_EQ(Drape(bad).status().code(), absl::StatusCode::kInvalidArgument);
  bad.supports.cuffs = {hem, hem};
  EXPECT_EQ(Drape(bad).status().code(), absl::StatusCode::kInvalidArgument);
}

// The body below the waist grows 40% longer, and the skirt's stiction pulls it down with the
// skin below.
class LongerBodyTest : public DrapeTest {
 protected:
  // The body below the waist (y < 0) stretched by `factor` in height.
  DrapeInput BelowWaist(double factor) const {
    DrapeInput input = Input(1.0, 1.0);
    for (Eigen::Index v = 0; v < input.target_body.rows(); ++v) {
      if (input.target_body(v, 1) < 0) input.target_body(v, 1) *= factor;
    }
    return input;
  }
  DrapeInput Longer() const { return BelowWaist(1.4); }
  double BandHeight(const DrapeResult& r) const {
    double sum = 0;
    for (int32_t v : top().vertices) sum += r.positions(v, 1);
    return sum / static_cast<double>(top().vertices.size());
  }
};

TEST_F(LongerBodyTest, FrictionLetsTheSkirtSlipWhereTheTiesDragTheWaistbandDown) {
  // The band held only as softly as before the supports, to show the ties' pull.
  ClothSettings ties;
  ties.waistband_anchor_stiffness = kUnsupportedAnchorStiffness;
  ClothSettings friction = ties;
  friction.friction = 0.4;
  auto tied = Drape(Longer(), ties);
  auto slipping = Drape(Longer(), friction);
  ASSERT_TRUE(tied.ok() && slipping.ok());
  std::printf("waistband height, mm: friction %.2f, ties %.2f\n", 1000 * BandHeight(*slipping),
              1000 * BandHeight(*tied));
  EXPECT_NEAR(BandHeight(*slipping), 0.0, 0.005);
  EXPECT_LT(BandHeight(*tied), BandHeight(*slipping) - 0.005);
}

// Friction has memory, so a drape with it is a path; solved at every step, the path's end does
// not depend on how finely it is walked.
TEST_F(LongerBodyTest, FrictionGivesTheSameDrapeOnTwiceTheSchedule) {
  ClothSettings friction;
  friction.friction = 0.4;
  const DrapeSchedule twice{.homotopy_steps = 2 * DrapeSchedule{}.homotopy_steps,
                            .relax_steps = 2 * DrapeSchedule{}.relax_steps};
  auto once = Drape(Longer(), friction);
  auto again = Drape(Longer(), friction);
  auto doubled = Drape(Longer(), friction, twice);
  ASSERT_TRUE(once.ok() && again.ok() && doubled.ok());
  EXPECT_EQ(Hash(once->positions), Hash(again->positions));
  const double moved = (once->positions - doubled->positions).rowwise().norm().mean();
  std::printf("twice the schedule moves the drape by %.3f mm mean\n", 1000 * moved);
  EXPECT_LT(moved, 0.0005);
}

// A cuff pressed onto the body by its elastic grips by friction, where the ties hold every
// vertex only as weakly as cloth clings: on the longer body the skin under the hem moves
// down, and the cuff's friction carries the hem further with it than the ties do (0.5 mm: the
// skirt's cloth, held at the waist by the band, takes the pull and the cuff slips).
TEST_F(LongerBodyTest, ACuffsFrictionHoldsItToTheSkinHarderThanTheTies) {
  const int32_t hem = hem_index_;
  ASSERT_GE(hem, 0);
  DrapeInput cuffed = Longer();
  cuffed.supports.cuffs = {hem};
  auto hem_height = [&](const DrapeResult& r) {
    double sum = 0;
    for (int32_t v : model_.openings[hem].vertices) sum += r.positions(v, 1);
    return sum / static_cast<double>(model_.openings[hem].vertices.size());
  };
  ClothSettings gripping;
  gripping.cuff_friction = 1;
  const DrapeSchedule twice{.homotopy_steps = 2 * DrapeSchedule{}.homotopy_steps,
                            .relax_steps = 2 * DrapeSchedule{}.relax_steps};
  auto tied = Drape(cuffed);
  auto held = Drape(cuffed, gripping);
  auto again = Drape(cuffed, gripping);
  auto doubled = Drape(cuffed, gripping, twice);
  ASSERT_TRUE(tied.ok() && held.ok() && again.ok() && doubled.ok());
  std::printf("hem height, mm: cuff friction %.2f, ties %.2f; band %.2f and %.2f\n",
              1000 * hem_height(*held), 1000 * hem_height(*tied), 1000 * BandHeight(*held),
              1000 * BandHeight(*tied));
  EXPECT_LT(hem_height(*held), hem_height(*tied) - 0.00025);
  EXPECT_EQ(held->metrics.penetration_below_0mm, 0.0);
  EXPECT_EQ(Hash(held->positions), Hash(again->positions));
  const double moved = (held->positions - doubled->positions).rowwise().norm().mean();
  std::printf("twice the schedule moves the drape by %.3f mm mean\n", 1000 * moved);
  EXPECT_LT(moved, 0.0005);
}

TEST_F(LongerBodyTest, TheSupportsHoldTheWaistbandAgainstUnlimitedStiction) {
  const ClothSettings supports;
  ClothSettings soft = supports;
  soft.waistband_anchor_stiffness = kUnsupportedAnchorStiffness;
  auto supported = Drape(Longer(), supports);
  auto held_softly = Drape(Longer(), soft);
  ASSERT_TRUE(supported.ok() && held_softly.ok());
  EXPECT_EQ(supports.friction, 0);
  EXPECT_NEAR(BandHeight(*supported), 0.0, 0.003);
  EXPECT_LT(BandHeight(*held_softly), BandHeight(*supported) - 0.003);
}

TEST_F(LongerBodyTest, OnAnAvatarAWaistbandKeepsItsPlaceOnTheRiseAsTheSkinSlidesOverIt) {
  // The hourglass as an avatar: padded to the avatar's vertex count, the padding in no
  // triangle and far to the side, with the crotch 30 cm below the band and the navel 5 cm
  // above it. On the target the landmarks move down 6 cm and the skin stays: the skin sliding
  // over the landmarks, as it does between avatars.
  DrapeInput input = Input(1.0, 1.0);
  auto as_avatar = [](const core::Positions& body, double landmark_shift) {
    core::Positions avatar = core::Positions::Constant(body::kBodyVertexCount, 3, 1.0);
    avatar.topRows(body.rows()) = body;
    avatar.row(body::BodyLandmarks::kCrotch) << 1.0, -0.30 + landmark_shift, 0.0;
    avatar.row(body::BodyLandmarks::kNavel) << 1.0, 0.05 + landmark_shift, 0.0;
    return avatar;
  };
  const core::Positions avatar = as_avatar(mean_.positions, 0.0);
  const core::Positions slid_avatar = as_avatar(mean_.positions, -0.06);
  input.mean_body = avatar;
  input.target_body = slid_avatar;
  auto slid = Drape(input);
  input.target_body = avatar;
  auto still = Drape(input);
  ASSERT_TRUE(slid.ok() && still.ok()) << slid.status() << still.status();
  // Where the band sits on the rise, 0 at the crotch and 1 at the navel.
  auto share = [&](const DrapeResult& r, const core::Positions& body) {
    const double crotch = body(body::BodyLandmarks::kCrotch, 1);
    return (BandHeight(r) - crotch) / (body(body::BodyLandmarks::kNavel, 1) - crotch);
  };
  std::printf("band on the rise: %.4f with the landmarks still, %.4f moved 6 cm down\n",
              share(*still, avatar), share(*slid, slid_avatar));
  EXPECT_NEAR(share(*slid, slid_avatar), share(*still, avatar), 0.01);
  EXPECT_NEAR(BandHeight(*slid), BandHeight(*still) - 0.06, 0.004);
}

TEST_F(LongerBodyTest, ACollarHoldsItsHeightWhereTheClothBelowPushesItUp) {
  // The body below the ring grows 40% shorter instead, and the ring is a collar, not a
  // waistband. The stiction carries the cloth below it up with the skin, and what the
  // fabric resists being shortened pushes the ring up, as a shirt's front pushes its collar
  // up a shorter man's neck.
  DrapeInput shorter = BelowWaist(0.6);
  shorter.supports = {.waistband_edges = {}, .collars = {top_index_}, .straps = {}};
  auto held = Drape(shorter);
  auto soft = Drape(shorter, WithoutSupports({}));
  // Straps (a bib overall's top edge) are held as a collar is.
  shorter.supports = {.waistband_edges = {}, .collars = {}, .straps = {top_index_}};
  auto strap = Drape(shorter);
  // Not a support (an open front, a button): held as softly as before the supports.
  shorter.supports = {};
  auto no_support = Drape(shorter);
  ASSERT_TRUE(held.ok() && soft.ok() && strap.ok() && no_support.ok());
  EXPECT_EQ(Hash(strap->positions), Hash(held->positions));
  std::printf("collar height, mm: held %.2f, as softly as before the supports %.2f\n",
              1000 * BandHeight(*held), 1000 * BandHeight(*soft));
  EXPECT_LT(std::abs(BandHeight(*held)), 0.5 * std::abs(BandHeight(*soft)));
  EXPECT_EQ(Hash(no_support->positions), Hash(soft->positions));
}

TEST_F(DrapeTest, RejectsSupportsOutOfOrderOrRange) {
  DrapeInput input = Input(1.0, 1.0);
  input.supports.waistband_edges = {3, 2};
  EXPECT_EQ(Drape(input).status().code(), absl::StatusCode::kInvalidArgument);
  input.supports.waistband_edges = {static_cast<int32_t>(model_.edges.size())};
  EXPECT_EQ(Drape(input).status().code(), absl::StatusCode::kInvalidArgument);
  input.supports = {.waistband_edges = {}, .collars = {top_index_, top_index_}, .straps = {}};
  EXPECT_EQ(Drape(input).status().code(), absl::StatusCode::kInvalidArgument);
  input.supports.collars = {static_cast<int32_t>(model_.openings.size())};
  EXPECT_EQ(Drape(input).status().code(), absl::StatusCode::kInvalidArgument);
  input.supports = {.waistband_edges = {}, .collars = {}, .straps = {-1}};
  EXPECT_EQ(Drape(input).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST_F(DrapeTest, LargerSizeSitsLooser) {
  auto small = Drape(Input(1.0, 0.9));
  auto large = Drape(Input(1.0, 1.2));
  ASSERT_TRUE(small.ok() && large.ok());
  EXPECT_GT(large->metrics.ease_mean_mm, small->metrics.ease_mean_mm + 5.0);
  EXPECT_GT(small->metrics.stretch_p99, large->metrics.stretch_p99);
}

TEST_F(DrapeTest, TheCarriedGirthRatioIsHowMuchTooNarrowTheSizeIsForTheBody) {
  auto girth_ratio = [&](const DrapeInput& in) {
    auto body = core::TriangleBvh::Build(in.mean_body, in.body_triangles);
    EXPECT_TRUE(body.ok());
    if (!body.ok()) return 0.0;
    const ClothSolver solver(model_, in.start, in.edge_rest, in.hinge_rest, in.supports, *body,
                             ClothSettings{});
    return solver.CarriedGirthRatio(in.target_body, in.body_triangles);
  };
  EXPECT_NEAR(girth_ratio(Input(1.0, 1.0)), 1.0, 1e-9);
  // A size cut 10% narrower and shorter, on the body it was made for.
  EXPECT_NEAR(girth_ratio(Input(1.0, 0.9)), 1 / 0.9, 1e-9);
  // The skirt hangs 2.5 cm off the waist, and its offset is carried as it is: a body 10% larger
  // all round widens it by less.
  const double wider = girth_ratio(Input(1.1, 1.0));
  EXPECT_GT(wider, 1.05);
  EXPECT_LT(wider, 1.1);
  // A body only longer leaves the skirt's girth as it was: only its length grows.
  DrapeInput longer = Input(1.0, 1.0);
  longer.target_body.col(1) *= 1.1;
  EXPECT_LT(girth_ratio(longer), 1.01);
}

TEST(TightTieFactorTest, FirmsFromNoneToTheFullFactorAcrossTheRamp) {
  const ClothSettings settings;
  EXPECT_EQ(TightTieFactor(settings, settings.tight_girth_from - 0.01), 1.0);
  EXPECT_DOUBLE_EQ(TightTieFactor(settings, settings.tight_girth_full + 0.01),
                   settings.tight_tie_factor);
  // Halfway the smoothstep is at a half, the factor at its square root.
  EXPECT_NEAR(
      TightTieFactor(settings, 0.5 * (settings.tight_girth_from + settings.tight_girth_full)),
      std::sqrt(settings.tight_tie_factor), 1e-9);
  // No jump: a step in the ratio moves the factor's logarithm by at most the smoothstep's
  // steepest slope, 1.5 over the ramp's width.
  const double step = 0.001;
  const double steepest = 1.5 * std::log(settings.tight_tie_factor) * step /
                          (settings.tight_girth_full - settings.tight_girth_from);
  double last = 1;
  for (double ratio = settings.tight_girth_from - 0.05; ratio < settings.tight_girth_full + 0.05;
       ratio += step) {
    const double factor = TightTieFactor(settings, ratio);
    EXPECT_GE(factor, last);
    EXPECT_LE(std::log(factor / last), steepest * (1 + 1e-9)) << "at a ratio of " << ratio;
    last = factor;
  }
  EXPECT_EQ(last, settings.tight_tie_factor);
}

TEST(TightTieFactorTest, TheCheckTakesTheDefaultAndNamesWhatItRefuses) {
  using ::testing::HasSubstr;
  EXPECT_TRUE(CheckTightTies(ClothSettings{}).ok());
  ClothSettings never;
  never.tight_tie_factor = 1;
  EXPECT_TRUE(CheckTightTies(never).ok());
  const auto refused = [](auto change) {
    ClothSettings settings;
    change(settings);
    const absl::Status status = CheckTightTies(settings);
    EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
    return std::string(status.message());
  };
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  EXPECT_THAT(refused([](ClothSettings& s) { s.tight_tie_factor = 0.5; }),
              HasSubstr("tight_tie_factor"));
  EXPECT_THAT(refused([](ClothSettings& s) { s.tight_tie_factor = kMaxTightTieFactor * 2; }),
              HasSubstr("tight_tie_factor"));
  EXPECT_THAT(refused([&](ClothSettings& s) { s.tight_tie_factor = kNaN; }),
              HasSubstr("tight_tie_factor"));
  EXPECT_THAT(refused([&](ClothSettings& s) { s.tight_girth_from = kInf; }),
              HasSubstr("tight_girth_from"));
  EXPECT_THAT(refused([](ClothSettings& s) { s.tight_girth_full = 3; }),
              HasSubstr("tight_girth_full"));
  // A ramp that ends before it starts.
  EXPECT_THAT(refused([](ClothSettings& s) {
                s.tight_girth_from = 1.1;
                s.tight_girth_full = 1.0;
              }),
              HasSubstr("is over tight_girth_full"));
}

TEST_F(DrapeTest, TiesFirmOnASizeTooSmallAndNotOnOneThatFits) {
  ClothSettings never = ClothSettings{};
  never.tight_tie_factor = 1;
  // 11% too narrow for the waist it was made for: firm ties move the drape.
  auto firm = Drape(Input(1.0, 0.9));
  auto soft = Drape(Input(1.0, 0.9), never);
  ASSERT_TRUE(firm.ok() && soft.ok());
  EXPECT_GT(firm->carried_girth_ratio, ClothSettings{}.tight_girth_full);
  EXPECT_EQ(firm->tie_factor, ClothSettings{}.tight_tie_factor);
  EXPECT_EQ(soft->tie_factor, 1);
  EXPECT_GT(1000 * (firm->positions - soft->positions).rowwise().norm().maxCoeff(), 0.1);
  // 10% wider than it: the same drape to the bit.
  auto fits = Drape(Input(1.0, 1.1));
  auto fits_never = Drape(Input(1.0, 1.1), never);
  ASSERT_TRUE(fits.ok() && fits_never.ok());
  EXPECT_LT(fits->carried_girth_ratio, ClothSettings{}.tight_girth_from);
  EXPECT_EQ(fits->tie_factor, 1);
  EXPECT_EQ(Hash(fits->positions), Hash(fits_never->positions));
}

TEST_F(DrapeTest, ConvergesUnderTheFixedBudget) {
  // Both a snug band and the free hem of the skirt come to rest: the last step moves no
  // vertex by more than a micrometer, or twenty where the size is too small for the body and its
  // band is held more firmly (TightTieFactor), which Newton resolves more slowly.
  const core::Mesh band = Tube(0.16, -0.06, 0.06, 6, 24);
  auto model = BuildClothModel(band.positions, band.faces, 0.2);
  ASSERT_TRUE(model.ok());
  auto snug = Drape(BandInput(band, *model, 0.9));
  ASSERT_TRUE(snug.ok());
  EXPECT_LT(snug->converged_max_move_mm, 1e-3);
  auto skirt = Drape(Input(1.1, 1.2));
  ASSERT_TRUE(skirt.ok());
  EXPECT_LT(skirt->converged_max_move_mm, 1e-3);
  auto tight = Drape(Input(1.1, 1.0));
  ASSERT_TRUE(tight.ok());
  EXPECT_LT(tight->converged_max_move_mm, 2e-2);
}

TEST_F(DrapeTest, DoublingTheBudgetBarelyMovesTheResult) {
  auto once = Drape(Input(1.1, 1.0));
  const DrapeSchedule usual;
  auto twice = Drape(Input(1.1, 1.0), {},
                     DrapeSchedule{.homotopy_steps = 2 * usual.homotopy_steps,
                                   .relax_steps = 2 * usual.relax_steps});
  ASSERT_TRUE(once.ok() && twice.ok());
  EXPECT_LT(1000 * (twice->positions - once->positions).rowwise().norm().mean(), 0.5);
}

TEST_F(DrapeTest, TheRelaxationSolvesWhatThePathLeft) {
  // The default settings take at most ClothSettings::path_newton_iterations on the path and
  // stop a relaxation step once an iteration moves no vertex by 0.1 mm: the result is within
  // that tolerance of solving every step exactly (0.05 mm here; 0.01 mm when every step of
  // the path was solved too), where a fixed single iteration per step is not (8 mm). The
  // path's capped steps alone end short of the minimum (1.5 mm): only they are capped, and
  // the relaxation solves what they leave. The cap cannot go to one iteration: the
  // relaxation then ends 8 mm off too. The stiff waistband elastic and its anchor converge
  // last.
  // With the ties of a size that fits: on this body, 30% larger, the size is too small and its
  // firm ties make every step all but quadratic, so that one iteration nears the minimum.
  ClothSettings soft_ties;
  soft_ties.tight_tie_factor = 1;
  ClothSettings exact = soft_ties;
  exact.newton_iterations = 200;
  exact.path_newton_iterations = 200;
  exact.newton_tolerance = 1e-9;
  ClothSettings single = soft_ties;
  single.newton_iterations = 1;
  single.path_newton_iterations = 1;
  const DrapeSchedule no_relax{.homotopy_steps = DrapeSchedule{}.homotopy_steps,
                               .relax_steps = 0};
  auto solved = Drape(Input(1.3, 1.0), soft_ties);
  auto reference = Drape(Input(1.3, 1.0), exact);
  auto rough = Drape(Input(1.3, 1.0), single);
  auto path_only = Drape(Input(1.3, 1.0), soft_ties, no_relax);
  ASSERT_TRUE(solved.ok() && reference.ok() && rough.ok() && path_only.ok());
  auto off_mm = [&](const DrapeResult& r) {
    return 1000 * (r.positions - reference->positions).cwiseAbs().maxCoeff();
  };
  const double solved_off = off_mm(*solved);
  const double rough_off = off_mm(*rough);
  const double path_off = off_mm(*path_only);
  std::printf(
      "off the exact solve, mm: solved %.4f, one iteration a step %.4f, path alone %.4f\n",
      solved_off, rough_off, path_off);
  EXPECT_LT(solved_off, 1000 * ClothSettings{}.newton_tolerance);
  EXPECT_GT(rough_off, 50 * solved_off);
  EXPECT_GT(path_off, 10 * solved_off);
}

TEST_F(DrapeTest, VariesSmoothlyWithTheBody) {
  // The second difference over body scales 1.1 +- 0.005 (the body moves by under a
  // millimeter), held to the offline fitter's bound for real bodies: a drape that jumped
  // between nearby bodies (an adaptive stop, a path that depends on the body) shows more.
  auto minus = Drape(Input(1.095, 1.0));
  auto mid = Drape(Input(1.1, 1.0));
  auto plus = Drape(Input(1.105, 1.0));
  ASSERT_TRUE(minus.ok() && mid.ok() && plus.ok());
  const double second =
      1000 * (plus->positions + minus->positions - 2 * mid->positions).cwiseAbs().maxCoeff();
  EXPECT_LT(second, 1.0);
  // And the body did move the garment: the test would pass for a drape ignoring the body.
  EXPECT_GT(1000 * (plus->positions - minus->positions).cwiseAbs().maxCoeff(), 0.5);
}

TEST_F(DrapeTest, ATightCoarseBandKeepsItsTrianglesOffTheSkin) {
  // A band of 12 facets stretched round a finely tessellated waist: its corners keep the
  // collision offset, but each facet's chord over the round waist would pass 5 mm under it,
  // and the band's tension presses it in, as a size too small does on a large body.
  const core::Mesh band = Tube(0.115, -0.03, 0.03, 2, 12);
  auto model = BuildClothModel(band.positions, band.faces, 0.2);
  ASSERT_TRUE(model.ok());
  DrapeInput input = BandInput(band, *model, 0.9);
  input.target_body = 1.2 * mean_.positions;
  auto result = Drape(input);
  ASSERT_TRUE(result.ok()) << result.status();
  // Every body vertex the band covers lies at least a millimetre under the band's surface.
  auto garment = core::TriangleBvh::Build(result->positions, model->triangles);
  ASSERT_TRUE(garment.ok());
  int covered = 0;
  double lowest = std::numeric_limits<double>::infinity();
  for (Eigen::Index v = 0; v < input.target_body.rows(); ++v) {
    const Eigen::Vector3d p = input.target_body.row(v).transpose();
    if (std::abs(p.y()) > 0.02) continue;
    const Eigen::Vector3d outward = Eigen::Vector3d(p.x(), 0, p.z()).normalized();
    const core::SurfacePoint cloth = garment->Closest(p, 0.02);
    ASSERT_TRUE(cloth.found) << "body vertex " << v << " is not under the band";
    lowest = std::min(lowest, (cloth.point - p).dot(outward));
    ++covered;
  }
  std::printf("band over %d body vertices, lowest %.2f mm above them\n", covered, 1000 * lowest);
  EXPECT_GE(covered, 32);  // The waist's ring of vertices.
  EXPECT_GT(lowest, 0.001);
}

TEST_F(DrapeTest, RejectsBadInput) {
  DrapeInput wrong_body = Input(1.0, 1.0);
  wrong_body.target_body.conservativeResize(10, 3);
  EXPECT_EQ(Drape(wrong_body).status().code(), absl::StatusCode::kInvalidArgument);
  DrapeInput nan_body = Input(1.0, 1.0);
  nan_body.target_body(3, 1) = std::nan("");
  EXPECT_EQ(Drape(nan_body).status().code(), absl::StatusCode::kInvalidArgument);
  DrapeInput bad_rest = Input(1.0, 1.0);
  bad_rest.edge_rest(0) = -0.01;
  EXPECT_EQ(Drape(bad_rest).status().code(), absl::StatusCode::kInvalidArgument);
  DrapeInput bad_angle = Input(1.0, 1.0);
  bad_angle.hinge_rest(0) = std::nan("");
  EXPECT_EQ(Drape(bad_angle).status().code(), absl::StatusCode::kInvalidArgument);
  bad_angle.hinge_rest(0) = 4.0;
  EXPECT_EQ(Drape(bad_angle).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(GarmentTemplateTest, PushesAPlacementOutOfTheBody) {
  const core::Mesh body = UvSphere(0.15, 16, 24);
  const core::Mesh tube = Tube(0.13, -0.05, 0.05, 4, 24);  // Starts 2 cm inside.
  auto fitted = FitTemplateToBody(tube.positions, tube.positions, tube.faces, body.positions,
                                  core::Triangulate(body.faces));
  ASSERT_TRUE(fitted.ok()) << fitted.status();
  auto bvh = core::TriangleBvh::Build(body.positions, core::Triangulate(body.faces));
  for (Eigen::Index v = 0; v < fitted->rows(); ++v) {
    EXPECT_GE(bvh->Closest(fitted->row(v).transpose(), 1.0).signed_distance, 0.0) << v;
  }
}

}  // namespace
}  // namespace fitbase::workers
