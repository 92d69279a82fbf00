// The calibrated presets. Per avatar, draws happen in this order: the coin (`all` only),
// gender, age_years, muscle, proportions, the three ethnic shares, breast_size and
// breast_firmness (women), the uncalibrated modifiers in ShapeModifiers() order (men skip the
// breast ones), then five standard normals z (truncated to +-3) that make the survey target
// mean + sd * (L z), L the Cholesky factor of the survey's correlations.
//
// | parameter                          | women                      | men                       |
// | ---------------------------------- | -------------------------- | ------------------------- |
// | gender                             | TN(0.05, 0.05) [0, 0.25]   | TN(0.95, 0.05) [0.75, 1]  |
// | age_years                          | uniform [25, 70]           | same                      |
// | muscle                             | TN(0.5, 0.1) [0.25, 0.75]  | same                      |
// | proportions                        | TN(0.5, 0.1) [0.3, 0.7]    | same                      |
// | african, asian, caucasian          | Dirichlet(1, 1, 1)         | same                      |
// | breast_size, breast_firmness       | TN(0.5, 0.1) [0.2, 0.8]    | 0.5 (default)             |
// | the wide presets' shape modifiers  | their distribution at half | same (breast ones 0)      |
// | but bust, waist, hips circumference| the spread: TN(0, 0.1)     |                           |
// |                                    | [-0.3, 0.3], pregnant half |                           |
// | height                             | solved for stature                                     |
// | mass, bust, waist, hips bundles    | solved for weight, bust, navel waist and hip girth,    |
// |                                    | added to the free values (kBundles)                    |
//
// The free parameters vary the shape the survey's five measurements do not fix, at half the
// wide presets' spread: at the wide spread they alone move stature and girths by more than the
// survey's SDs, and the solver would spend its sliders undoing them.

#include "body/population_calibration.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "Eigen/Cholesky"
#include "Eigen/LU"
#include "absl/strings/str_cat.h"
#include "core/random.h"
#include "core/status_macros.h"

namespace fitbase::body {
namespace {

constexpr int kN = kSurveyMeasurementCount;
using Vector = Eigen::Matrix<double, kN, 1>;

const SurveyTable kAnsurWomen = {
    .name = "ANSUR II women (n = 1,986)",
    .mean = {1.6285, 67.7582, 0.9469, 0.8609, 1.0212},
    .sd = {0.0642, 10.9846, 0.0827, 0.0999, 0.0759},
    .correlation = {{{1.000, 0.533, 0.260, 0.229, 0.379},
                     {0.533, 1.000, 0.829, 0.836, 0.913},
                     {0.260, 0.829, 1.000, 0.844, 0.743},
                     {0.229, 0.836, 0.844, 1.000, 0.803},
                     {0.379, 0.913, 0.743, 0.803, 1.000}}},
};

const SurveyTable kAnsurMen = {
    .name = "ANSUR II men (n = 4,082)",
    .mean = {1.7562, 85.5240, 1.0587, 0.9406, 1.0195},
    .sd = {0.0686, 14.2207, 0.0874, 0.1117, 0.0767},
    .correlation = {{{1.000, 0.469, 0.247, 0.208, 0.340},
                     {0.469, 1.000, 0.907, 0.888, 0.933},
                     {0.247, 0.907, 1.000, 0.886, 0.836},
                     {0.208, 0.888, 0.886, 1.000, 0.876},
                     {0.340, 0.933, 0.836, 0.876, 1.000}}},
};

constexpr TruncatedNormalSpec kMuscle = {0.5, 0.1, 0.25, 0.75};
constexpr TruncatedNormalSpec kProportions = {0.5, 0.1, 0.3, 0.7};
constexpr TruncatedNormalSpec kBreast = {0.5, 0.1, 0.2, 0.8};
constexpr double kMaxZ = 3.0;

constexpr absl::string_view kBustModifier = "measure/measure-bust-circ-decr|incr";
constexpr absl::string_view kWaistModifier = "measure/measure-waist-circ-decr|incr";
constexpr absl::string_view kHipsModifier = "measure/measure-hips-circ-decr|incr";

// The solved parameters, in kSurveyMeasurements order, each a direction in parameter space:
// height (stature); mass, the weight and muscle sliders with the modifiers that carry a heavier
// body's volume outside the torso's girths (weight); and the bust, waist and hips bundles.
// MakeHuman's weight slider alone adds only 7 kg from average to maximum on the default woman
// (48 to 55 kg) and its circumference modifiers at most 10 cm, while the survey's women weigh
// 68 kg on average and 90 kg at +2 SD: the bundles reach 94 kg, a 122 cm bust, a 109 cm navel
// waist and a 124 cm hip on a 1.59 m woman.
using Controls = Vector;
constexpr std::array<double, kN> kLow = {0, -1, -1, -1, -1};
// Mass and waist run to 2: their sliders saturate one after the other (the weight slider and
// the waist modifier at 1, the modifiers of gain 0.5 at 2).
constexpr std::array<double, kN> kHigh = {1, 2, 1, 2, 1};
// Forward-difference steps of the reference Jacobian.
constexpr std::array<double, kN> kStep = {0.05, 0.2, 0.2, 0.2, 0.2};

struct BundleTerm {
  int control;
  absl::string_view modifier;
  double gain;
};

constexpr BundleTerm kBundles[] = {
    {1, "measure/measure-thigh-circ-decr|incr", 0.6},
    {1, "measure/measure-upperarm-circ-decr|incr", 0.6},
    {1, "measure/measure-calf-circ-decr|incr", 0.5},
    {1, "measure/measure-neck-circ-decr|incr", 0.5},
    {1, "buttocks/buttocks-volume-decr|incr", 0.5},
    {1, "torso/torso-scale-depth-decr|incr", 0.5},
    {2, kBustModifier, 1.0},
    {2, "torso/torso-scale-horiz-decr|incr", 0.6},
    {3, kWaistModifier, 1.0},
    {3, "stomach/stomach-pregnant-decr|incr", 0.6},
    {4, kHipsModifier, 1.0},
    {4, "hip/hip-scale-horiz-decr|incr", 0.6},
    {4, "hip/hip-scale-depth-decr|incr", 0.4},
};

// Broyden stops once every measurement is this close to its target: under a tenth of the
// survey's SD, and under ISO 20685-1's allowances for stature (4 mm) and large girths (9 mm).
constexpr std::array<double, kN> kTolerance = {0.001, 0.2, 0.002, 0.002, 0.002};
constexpr int kMaxEvaluations = 16;

// The free parameters an avatar drew, which the controls add to.
struct FreeBody {
  BodyParams params;
  double muscle;
  double breast_size;
};

BodyParams Controlled(const FreeBody& free, const Controls& c) {
  BodyParams params = free.params;
  params.height = c(0);
  params.weight = std::clamp(0.5 + 0.5 * c(1), 0.0, 1.0);
  params.muscle = std::clamp(free.muscle + 0.25 * c(1), 0.0, 1.0);
  // A woman's bust is mostly her breasts': the bust bundle moves the cup size too.
  if (params.gender < 0.5) {
    params.breast_size = std::clamp(free.breast_size + 0.3 * c(2), 0.0, 1.0);
  }
  params.modifiers[std::string(kBustModifier)] = 0;
  params.modifiers[std::string(kWaistModifier)] = 0;
  params.modifiers[std::string(kHipsModifier)] = 0;
  for (const BundleTerm& term : kBundles) {
    double& value = params.modifiers[std::string(term.modifier)];
    value = std::clamp(value + term.gain * c(term.control), -1.0, 1.0);
  }
  return params;
}

double Draw(core::Random& random, const TruncatedNormalSpec& spec) {
  return random.TruncatedNormal(spec.mean, spec.sd, spec.lo, spec.hi);
}

Controls Clamp(Controls c) {
  for (int i = 0; i < kN; ++i) c(i) = std::clamp(c(i), kLow[i], kHigh[i]);
  return c;
}

Controls Middle() {
  Controls c;
  for (int i = 0; i < kN; ++i) c(i) = (kLow[i] + kHigh[i]) / 2;
  return c;
}

// A woman's or a man's free parameters.
FreeBody SampleFree(bool woman, core::Random& random) {
  BodyParams params;
  params.gender = Draw(random, woman ? kWomenGender : kMenGender);
  params.age_years = random.Uniform(25.0, 70.0);
  params.muscle = Draw(random, kMuscle);
  params.proportions = Draw(random, kProportions);
  DrawEthnicShares(random, params);
  if (woman) {
    params.breast_size = Draw(random, kBreast);
    params.breast_firmness = Draw(random, kBreast);
  }
  // The wide presets' shape modifiers at half their spread, but for the three the bundles
  // set: the solver needs those free.
  for (const ShapeModifier& modifier : ShapeModifiers()) {
    if (modifier.name == kBustModifier || modifier.name == kWaistModifier ||
        modifier.name == kHipsModifier) {
      continue;
    }
    const TruncatedNormalSpec& wide = modifier.distribution;
    const TruncatedNormalSpec narrow = {wide.mean, wide.sd / 2, wide.lo / 2, wide.hi / 2};
    params.modifiers.emplace(std::string(modifier.name),
                             modifier.women_only && !woman ? 0.0 : Draw(random, narrow));
  }
  return FreeBody{.params = params, .muscle = params.muscle, .breast_size = params.breast_size};
}

Vector TargetOf(const SurveyTable& table, core::Random& random) {
  Eigen::Matrix<double, kN, kN> correlation;
  for (int i = 0; i < kN; ++i) {
    for (int j = 0; j < kN; ++j) correlation(i, j) = table.correlation[i][j];
  }
  const Eigen::Matrix<double, kN, kN> lower = correlation.llt().matrixL();
  Vector z;
  for (int i = 0; i < kN; ++i) z(i) = random.TruncatedNormal(0, 1, -kMaxZ, kMaxZ);
  const Vector standard = lower * z;
  Vector target;
  for (int i = 0; i < kN; ++i) target(i) = table.mean[i] + table.sd[i] * standard(i);
  return target;
}

}  // namespace

const SurveyTable& AnsurWomen() { return kAnsurWomen; }
const SurveyTable& AnsurMen() { return kAnsurMen; }

absl::StatusOr<PopulationSampler> PopulationSampler::Create(const BodyModel& model) {
  PopulationSampler sampler(model, core::Triangulate(model.body_faces()));
  for (bool woman : {true, false}) {
    FreeBody reference;
    reference.params.gender = woman ? 0.0 : 1.0;
    reference.muscle = reference.params.muscle;
    reference.breast_size = reference.params.breast_size;
    ASSIGN_OR_RETURN(const Vector at, sampler.MeasureSurvey(Controlled(reference, Middle())));
    Jacobian& jacobian = woman ? sampler.women_jacobian_ : sampler.men_jacobian_;
    for (int j = 0; j < kN; ++j) {
      Controls moved = Middle();
      moved(j) += kStep[j];
      ASSIGN_OR_RETURN(const Vector there, sampler.MeasureSurvey(Controlled(reference, moved)));
      jacobian.col(j) = (there - at) / kStep[j];
    }
  }
  return sampler;
}

absl::StatusOr<Vector> PopulationSampler::MeasureSurvey(const BodyParams& params) const {
  ASSIGN_OR_RETURN(const core::Mesh body, model_->BuildBody(params));
  ASSIGN_OR_RETURN(const BodyMeasurements m,
                   MeasureBody(body.positions, triangles_, kSurveyMeasurements));
  Vector v;
  for (int i = 0; i < kN; ++i) v(i) = m[static_cast<int>(kSurveyMeasurements[i])];
  return v;
}

absl::StatusOr<BodyParams> PopulationSampler::Sample(PopulationPreset preset, uint64_t seed,
                                                     uint64_t index) const {
  if (!IsCalibratedPreset(preset)) return SampleBodyParams(preset, seed, index);
  ASSIGN_OR_RETURN(CalibratedAvatar avatar, SampleCalibrated(preset, seed, index));
  return std::move(avatar.params);
}

absl::StatusOr<CalibratedAvatar> PopulationSampler::SampleCalibrated(PopulationPreset preset,
                                                                     uint64_t seed,
                                                                     uint64_t index) const {
  if (!IsCalibratedPreset(preset)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "preset ", PopulationPresetName(preset), " is not calibrated to a survey"));
  }
  core::Random random(seed, index);
  bool woman = preset == PopulationPreset::kWomen;
  if (preset == PopulationPreset::kAll) woman = random.Uniform01() < 0.5;
  const FreeBody free = SampleFree(woman, random);
  const Vector target = TargetOf(woman ? kAnsurWomen : kAnsurMen, random);

  // Broyden's method on the five controls, each step clamped to their ranges and halved while
  // it makes the worst scaled miss larger. A target beyond what the controls reach ends at the
  // nearest body they make.
  auto scaled_error = [&](const Vector& m) {
    double worst = 0;
    for (int i = 0; i < kN; ++i) {
      worst = std::max(worst, std::abs(m(i) - target(i)) / kTolerance[i]);
    }
    return worst;
  };
  Jacobian jacobian = woman ? women_jacobian_ : men_jacobian_;
  Controls controls = Middle();
  ASSIGN_OR_RETURN(Vector measured, MeasureSurvey(Controlled(free, controls)));
  int evaluations = 1;
  while (evaluations < kMaxEvaluations && scaled_error(measured) > 1) {
    Controls step = Clamp(controls - jacobian.partialPivLu().solve(measured - target)) - controls;
    if (step.squaredNorm() < 1e-16) break;
    bool improved = false;
    while (evaluations < kMaxEvaluations && step.squaredNorm() >= 1e-16) {
      ASSIGN_OR_RETURN(const Vector now, MeasureSurvey(Controlled(free, controls + step)));
      ++evaluations;
      jacobian += ((now - measured) - jacobian * step) * step.transpose() / step.squaredNorm();
      if (scaled_error(now) < scaled_error(measured)) {
        controls += step;
        measured = now;
        improved = true;
        break;
      }
      step /= 2;
    }
    if (!improved) break;
  }
  CalibratedAvatar avatar{.params = Controlled(free, controls), .target = {}, .measured = {}};
  for (int i = 0; i < kN; ++i) {
    avatar.target[i] = target(i);
    avatar.measured[i] = measured(i);
  }
  return avatar;
}

}  // namespace fitbase::body
