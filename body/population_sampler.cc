// The wide population presets (women-wide, men-wide, all-wide), sampled from the
// distributions below; population_calibration.cc has the calibrated ones. TN(m, s) [lo, hi]
// is a normal with mean m and standard deviation s conditioned on [lo, hi]
// (Random::TruncatedNormal); m and s are those of the normal before truncation.
//
// | parameter                            | women                      | men                      |
// | ------------------------------------ | -------------------------- | ------------------------ |
// | gender                               | TN(0.05, 0.05) [0, 0.25]   | TN(0.95, 0.05) [0.75, 1] |
// | age_years                            | uniform [25, 70]           | same                     |
// | muscle                               | TN(0.5, 0.12) [0.2, 0.85]  | same                     |
// | weight                               | TN(0.5, 0.15) [0.15, 0.9]  | same                     |
// | height                               | TN(0.5, 0.15) [0.15, 0.85] | same                     |
// | proportions                          | TN(0.5, 0.15) [0.2, 0.8]   | same                     |
// | african, asian, caucasian            | Dirichlet(1, 1, 1)         | same                     |
// | breast_size, breast_firmness         | TN(0.5, 0.15) [0.1, 0.9]   | 0.5 (default)            |
// | measure/* (all 20)                   | TN(0, 0.2) [-0.6, 0.6]     | same                     |
// | torso scale depth/horiz/vert, vshape | TN(0, 0.2) [-0.6, 0.6]     | same                     |
// | hip scale depth/horiz/vert, waist    | TN(0, 0.2) [-0.6, 0.6]     | same                     |
// | stomach-tone                         | TN(0, 0.2) [-0.6, 0.6]     | same                     |
// | stomach-pregnant                     | TN(0, 0.1) [-0.3, 0.3]     | same                     |
// | buttocks-volume                      | TN(0, 0.2) [-0.6, 0.6]     | same                     |
// | breast dist, point, volume-vert      | TN(0, 0.2) [-0.6, 0.6]     | 0                        |
//
// `all-wide` flips a fair coin per avatar and then samples the women or the men column.
// Caucasian is set to 1 - african - asian (clamped at 0) so the shares sum to 1 exactly enough
// for ValidateBodyParams. Translation modifiers (*-trans-*), navel and nipple modifiers are left
// out because they move or detail the surface rather than change the body's shape, and the torso
// muscle modifiers because the macro muscle parameter already drives musculature. Every avatar
// of every preset carries the same modifier keys, men holding 0 for the breast ones, so a
// dataset's parameter columns never depend on which avatars it holds.
//
// Per avatar, draws happen in this order: the coin (`all` only), gender, age_years, muscle,
// weight, height, proportions, the three ethnic shares, breast_size and breast_firmness (women),
// then the modifiers in kShapeModifiers order (men skip the breast ones).

#include "body/population_sampler.h"

#include <algorithm>
#include <array>
#include <string>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "core/random.h"

namespace fitbase::body {
namespace {

constexpr double kMinSampledAgeYears = 25.0;
constexpr double kMaxSampledAgeYears = 70.0;
constexpr TruncatedNormalSpec kMuscle = {0.5, 0.12, 0.2, 0.85};
constexpr TruncatedNormalSpec kWeight = {0.5, 0.15, 0.15, 0.9};
constexpr TruncatedNormalSpec kHeight = {0.5, 0.15, 0.15, 0.85};
constexpr TruncatedNormalSpec kProportions = {0.5, 0.15, 0.2, 0.8};
constexpr TruncatedNormalSpec kBreast = {0.5, 0.15, 0.1, 0.9};
constexpr TruncatedNormalSpec kShape = {0.0, 0.2, -0.6, 0.6};
// At full strength the pregnant target pushes the belly out by about 10 cm; a third of that
// covers ordinary bellies without sampling visible pregnancies.
constexpr TruncatedNormalSpec kPregnant = {0.0, 0.1, -0.3, 0.3};

constexpr ShapeModifier kShapeModifiers[] = {
    {"measure/measure-neck-circ-decr|incr", kShape, false},
    {"measure/measure-neck-height-decr|incr", kShape, false},
    {"measure/measure-upperarm-circ-decr|incr", kShape, false},
    {"measure/measure-upperarm-length-decr|incr", kShape, false},
    {"measure/measure-lowerarm-length-decr|incr", kShape, false},
    {"measure/measure-wrist-circ-decr|incr", kShape, false},
    {"measure/measure-frontchest-dist-decr|incr", kShape, false},
    {"measure/measure-bust-circ-decr|incr", kShape, false},
    {"measure/measure-underbust-circ-decr|incr", kShape, false},
    {"measure/measure-waist-circ-decr|incr", kShape, false},
    {"measure/measure-napetowaist-dist-decr|incr", kShape, false},
    {"measure/measure-waisttohip-dist-decr|incr", kShape, false},
    {"measure/measure-shoulder-dist-decr|incr", kShape, false},
    {"measure/measure-hips-circ-decr|incr", kShape, false},
    {"measure/measure-upperleg-height-decr|incr", kShape, false},
    {"measure/measure-thigh-circ-decr|incr", kShape, false},
    {"measure/measure-lowerleg-height-decr|incr", kShape, false},
    {"measure/measure-calf-circ-decr|incr", kShape, false},
    {"measure/measure-knee-circ-decr|incr", kShape, false},
    {"measure/measure-ankle-circ-decr|incr", kShape, false},
    {"torso/torso-scale-depth-decr|incr", kShape, false},
    {"torso/torso-scale-horiz-decr|incr", kShape, false},
    {"torso/torso-scale-vert-decr|incr", kShape, false},
    {"torso/torso-vshape-decr|incr", kShape, false},
    {"hip/hip-scale-depth-decr|incr", kShape, false},
    {"hip/hip-scale-horiz-decr|incr", kShape, false},
    {"hip/hip-scale-vert-decr|incr", kShape, false},
    {"hip/hip-waist-down|up", kShape, false},
    {"stomach/stomach-tone-decr|incr", kShape, false},
    {"stomach/stomach-pregnant-decr|incr", kPregnant, false},
    {"buttocks/buttocks-volume-decr|incr", kShape, false},
    {"breast/breast-dist-decr|incr", kShape, true},
    {"breast/breast-point-decr|incr", kShape, true},
    {"breast/breast-volume-vert-down|up", kShape, true},
};

struct PresetName {
  PopulationPreset preset;
  absl::string_view name;
};

constexpr PresetName kPresetNames[] = {
    {PopulationPreset::kWomen, "women"},
    {PopulationPreset::kMen, "men"},
    {PopulationPreset::kAll, "all"},
    {PopulationPreset::kWomenWide, "women-wide"},
    {PopulationPreset::kMenWide, "men-wide"},
    {PopulationPreset::kAllWide, "all-wide"},
};

double Draw(core::Random& random, const TruncatedNormalSpec& spec) {
  return random.TruncatedNormal(spec.mean, spec.sd, spec.lo, spec.hi);
}

BodyParams SampleAdult(bool woman, core::Random& random) {
  BodyParams params;
  params.gender = Draw(random, woman ? kWomenGender : kMenGender);
  params.age_years = random.Uniform(kMinSampledAgeYears, kMaxSampledAgeYears);
  params.muscle = Draw(random, kMuscle);
  params.weight = Draw(random, kWeight);
  params.height = Draw(random, kHeight);
  params.proportions = Draw(random, kProportions);

  DrawEthnicShares(random, params);

  if (woman) {
    params.breast_size = Draw(random, kBreast);
    params.breast_firmness = Draw(random, kBreast);
  }
  for (const ShapeModifier& modifier : kShapeModifiers) {
    const double value = modifier.women_only && !woman ? 0.0 : Draw(random, modifier.distribution);
    params.modifiers.emplace(std::string(modifier.name), value);
  }
  return params;
}

}  // namespace

std::span<const ShapeModifier> ShapeModifiers() { return kShapeModifiers; }

void DrawEthnicShares(core::Random& random, BodyParams& params) {
  std::array<double, 3> shares;
  random.FlatDirichlet(shares);
  params.african = shares[0];
  params.asian = shares[1];
  params.caucasian = std::max(0.0, 1.0 - shares[0] - shares[1]);
}

absl::StatusOr<PopulationPreset> ParsePopulationPreset(absl::string_view name) {
  for (const PresetName& entry : kPresetNames) {
    if (entry.name == name) return entry.preset;
  }
  return absl::InvalidArgumentError(absl::StrCat(
      "unknown population preset '", name, "'; valid presets: ",
      absl::StrJoin(kPresetNames, ", ",
                    [](std::string* out, const PresetName& entry) { out->append(entry.name.data(), entry.name.size()); })));
}

absl::string_view PopulationPresetName(PopulationPreset preset) {
  const auto* it =
      std::find_if(std::begin(kPresetNames), std::end(kPresetNames),
                   [preset](const PresetName& entry) { return entry.preset == preset; });
  return it == std::end(kPresetNames) ? absl::string_view() : it->name;
}

bool IsCalibratedPreset(PopulationPreset preset) {
  return preset == PopulationPreset::kWomen || preset == PopulationPreset::kMen ||
         preset == PopulationPreset::kAll;
}

BodyParams SampleBodyParams(PopulationPreset preset, uint64_t seed, uint64_t index) {
  core::Random random(seed, index);
  bool woman = preset == PopulationPreset::kWomen || preset == PopulationPreset::kWomenWide;
  if (preset == PopulationPreset::kAll || preset == PopulationPreset::kAllWide) {
    woman = random.Uniform01() < 0.5;
  }
  return SampleAdult(woman, random);
}

}  // namespace fitbase::body
