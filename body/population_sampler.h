#ifndef FITBASE_BODY_POPULATION_SAMPLER_H_
#define FITBASE_BODY_POPULATION_SAMPLER_H_

#include <cstdint>
#include <span>

#include "absl/strings/string_view.h"

#include "absl/status/statusor.h"
#include "body/body_params.h"
#include "core/random.h"

namespace fitbase::body {

// women, men and all reproduce a survey's adults (PopulationSampler); the -wide presets are
// the first, wide samplers (stature SD about 2.5 times the survey's), kept for stress tests.
enum class PopulationPreset { kWomen, kMen, kAll, kWomenWide, kMenWide, kAllWide };

absl::StatusOr<PopulationPreset> ParsePopulationPreset(absl::string_view name);
absl::string_view PopulationPresetName(PopulationPreset preset);
bool IsCalibratedPreset(PopulationPreset preset);

// A normal with mean `mean` and standard deviation `sd` conditioned on [lo, hi]
// (Random::TruncatedNormal): how the presets draw a parameter.
struct TruncatedNormalSpec {
  double mean;
  double sd;
  double lo;
  double hi;
};

// A local shape modifier the presets draw, with the wide presets' distribution.
struct ShapeModifier {
  absl::string_view name;
  TruncatedNormalSpec distribution;
  bool women_only;
};

// The wide presets' shape modifiers, in the order they are drawn.
std::span<const ShapeModifier> ShapeModifiers();

// Draws the ethnic shares of `params` from the flat Dirichlet(1, 1, 1), caucasian set to
// 1 - african - asian (clamped at 0) so the shares sum to 1 exactly enough for
// ValidateBodyParams.
void DrawEthnicShares(core::Random& random, BodyParams& params);

// The wide presets' gender draws: women near 0, men near 1.
inline constexpr TruncatedNormalSpec kWomenGender = {0.05, 0.05, 0.0, 0.25};
inline constexpr TruncatedNormalSpec kMenGender = {0.95, 0.05, 0.75, 1.0};

// Avatar number `index` of a wide population (preset, seed), from the distributions in
// population_sampler.cc; a calibrated preset gives its wide twin's avatar (PopulationSampler
// makes its survey bodies). Each avatar draws from its own generator seeded from (seed,
// index), so a population of N avatars is the prefix of one of N + M avatars, and the result
// is bit-identical on every platform.
BodyParams SampleBodyParams(PopulationPreset preset, uint64_t seed, uint64_t index);

}  // namespace fitbase::body

#endif  // FITBASE_BODY_POPULATION_SAMPLER_H_
