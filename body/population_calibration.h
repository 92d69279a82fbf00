#ifndef FITBASE_BODY_POPULATION_CALIBRATION_H_
#define FITBASE_BODY_POPULATION_CALIBRATION_H_

#include <array>
#include <cstdint>

#include "Eigen/Core"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "body/body_measurements.h"
#include "body/body_model.h"
#include "body/body_params.h"
#include "body/population_sampler.h"

namespace fitbase::body {

// The measurements a calibrated preset reproduces, in this order.
inline constexpr int kSurveyMeasurementCount = 5;
inline constexpr std::array<Measurement, kSurveyMeasurementCount> kSurveyMeasurements = {
    Measurement::kStature, Measurement::kWeight, Measurement::kBustGirth,
    Measurement::kNavelWaistGirth, Measurement::kHipGirth};

// A survey's summary table for one sex: mean and SD (m, kg) of kSurveyMeasurements and their
// correlations.
struct SurveyTable {
  absl::string_view name;
  std::array<double, kSurveyMeasurementCount> mean;
  std::array<double, kSurveyMeasurementCount> sd;
  std::array<std::array<double, kSurveyMeasurementCount>, kSurveyMeasurementCount> correlation;
};

// ANSUR II (Gordon et al. 2014, "2012 Anthropometric Survey of U.S. Army Personnel: Methods
// and Summary Statistics", NATICK/TR-15/007), computed from its public data files: 1,986 women
// and 4,082 men. Its chest circumference is taken at the bust point and its waist
// circumference at the navel (omphalion), as kBustGirth and kNavelWaistGirth are.
const SurveyTable& AnsurWomen();
const SurveyTable& AnsurMen();

// One avatar of a calibrated preset: its parameters, the measurements drawn for it from the
// survey, and those its body has.
struct CalibratedAvatar {
  BodyParams params;
  std::array<double, kSurveyMeasurementCount> target;
  std::array<double, kSurveyMeasurementCount> measured;
};

// Samples the presets. The calibrated ones (women, men, all) draw each avatar's stature,
// weight, bust, waist and hip jointly from the survey's normal distribution, its other
// parameters (age, ethnic mix, muscle, proportions, the local shape modifiers) from the
// narrow distributions in population_calibration.cc, then choose its height and four bundles
// of sliders (mass, bust, waist, hips) so that its body measures what was drawn (Broyden's
// method from a Jacobian measured once per sex, at most 16 bodies). The wide presets are
// SampleBodyParams's. Avatar i is the same in a population of any size, bit for bit.
class PopulationSampler {
 public:
  // Measures the reference bodies' Jacobians once (about 12 bodies). `model` must outlive the
  // sampler.
  static absl::StatusOr<PopulationSampler> Create(const BodyModel& model);

  absl::StatusOr<BodyParams> Sample(PopulationPreset preset, uint64_t seed, uint64_t index) const;

  // The same with the calibration's targets and results; INVALID_ARGUMENT for a wide preset.
  absl::StatusOr<CalibratedAvatar> SampleCalibrated(PopulationPreset preset, uint64_t seed,
                                                    uint64_t index) const;

 private:
  using Jacobian = Eigen::Matrix<double, kSurveyMeasurementCount, kSurveyMeasurementCount>;
  PopulationSampler(const BodyModel& model, core::Triangles triangles)
      : model_(&model), triangles_(std::move(triangles)) {}
  absl::StatusOr<Eigen::Matrix<double, kSurveyMeasurementCount, 1>> MeasureSurvey(
      const BodyParams& params) const;

  const BodyModel* model_;
  core::Triangles triangles_;
  Jacobian women_jacobian_;
  Jacobian men_jacobian_;
};

}  // namespace fitbase::body

#endif  // FITBASE_BODY_POPULATION_CALIBRATION_H_
