#ifndef FITBASE_PIPELINE_AVATAR_FROM_MEASUREMENTS_H_
#define FITBASE_PIPELINE_AVATAR_FROM_MEASUREMENTS_H_

#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "Eigen/Core"
#include "absl/status/statusor.h"
#include "body/body_measurements.h"
#include "core/mesh.h"
#include "fitbase/v1/avatar.pb.h"
#include "pipeline/avatar_projection.h"

namespace fitbase::pipeline {

// Measurements a person gave: meters, and kilograms for weight; each measurement once.
using MeasurementSet = std::vector<std::pair<body::Measurement, double>>;

// The set a TypedMeasurements message holds (cm and kg), converted to meters. INVALID_ARGUMENT
// naming the field: no measurement at all, no stature, a value that is not finite, or one
// outside what an adult body measures (e.g. stature 100 to 250 cm, weight 25 to 300 kg).
absl::StatusOr<MeasurementSet> MeasurementsFromProto(const v1::TypedMeasurements& typed);

// All of a body's measurements as a person reads them (cm, kg).
v1::TypedMeasurements MeasurementsToProto(const body::BodyMeasurements& measurements);

// How the bodies of an avatar basis measure, learned once per basis: bodies sampled from the
// basis's own population distribution (weights ~ N(0, diag sigma^2), seeded) are measured,
// giving the joint Gaussian of weights and measurements and the linear response of each
// measurement to the weights.
class MeasurementModel {
 public:
  // About 256 bodies measured: a second or so.
  static absl::StatusOr<MeasurementModel> Build(const LoadedAvatarBasis& basis);

  const Eigen::VectorXd& mean() const { return mean_; }  // kMeasurementCount, m and kg.
  // kMeasurementCount x N: d measurement / d weight (per meter of weight).
  const Eigen::MatrixXd& response() const { return response_; }
  // kMeasurementCount: the spread of each measurement the weights do not explain.
  const Eigen::VectorXd& residual_sd() const { return residual_sd_; }
  // The basis's mean avatar without its positions: the topology every made body shares.
  const core::Mesh& topology() const { return topology_; }
  const core::Triangles& triangles() const { return triangles_; }

 private:
  Eigen::VectorXd mean_;
  Eigen::MatrixXd response_;
  Eigen::VectorXd residual_sd_;
  core::Mesh topology_;
  core::Triangles triangles_;
};

struct MeasuredAvatar {
  Eigen::VectorXd weights;  // N, meters: the basis's weights.
  core::Mesh avatar;        // mean + components * weights, meters, with the basis's faces.
  // Per given measurement, in the order given: (measurement, given, reached), m and kg.
  std::vector<std::tuple<body::Measurement, double, double>> residuals;
  std::vector<std::string> out_of_distribution_reasons;  // Empty when in distribution.
};

// ISO 20685-1's allowance for a measurement: 4 mm for stature and small girths (neck, upper
// arm), 5 mm for lengths, 9 mm for large girths, 0.5 kg for weight.
double MeasurementAllowance(body::Measurement measurement);

// The body of `basis` that best matches `given`: the conditional Gaussian of the weights given
// the measurements as the start, then Gauss-Newton through the real measurement functions
// with a Mahalanobis prior on the weights (each given measurement weighted by its allowance).
// A set no body of the basis satisfies gets its best body and out-of-distribution reasons
// naming the residuals over their allowance and components beyond 4 sigma; never an error.
absl::StatusOr<MeasuredAvatar> AvatarFromMeasurements(const LoadedAvatarBasis& basis,
                                                      const MeasurementModel& model,
                                                      const MeasurementSet& given);

// The figures of AvatarFromMeasurements on `avatars` (bodies of the basis's topology, meters),
// as a Markdown table: each avatar measured by the project's own functions and fed back with
// three input sets ({stature, weight}; + bust, waist, hip; all 13), then the share of given
// measurements reproduced within MeasurementAllowance, the measurement missed most with the
// share of avatars that have it within its allowance, the number flagged out of distribution,
// and the
// per-vertex distance from the made body to the true one (mean of the avatars' means, and
// the 95th percentile over every vertex of every avatar).
absl::StatusOr<std::string> EvaluateAvatarFromMeasurements(
    const LoadedAvatarBasis& basis, const MeasurementModel& model,
    const std::vector<core::Mesh>& avatars);

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_AVATAR_FROM_MEASUREMENTS_H_
