#include "pipeline/avatar_from_measurements.h"

#include <algorithm>
#include <cmath>

#include "Eigen/Cholesky"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "body/body_model.h"
#include "core/random.h"
#include "core/status_macros.h"
#include "google/protobuf/descriptor.h"
#include "google/protobuf/reflection.h"
#include "proto/mesh_codec.h"

namespace fitbase::pipeline {
namespace {

// Bodies sampled to learn a basis's measurement model: enough that the 13 x N regression is
// determined 10 times over for N up to 25 components.
constexpr int kModelSamples = 256;
constexpr uint64_t kModelSeed = 0x6d65617375726573;  // "measures"
constexpr int kMaxIterations = 20;
// Components beyond this many sigmas mark a body outside the population (as ProjectAvatar).
constexpr double kOutOfDistributionSigmas = 4.0;

// What an adult body measures, cm (kg for weight): wider than any survey's range, narrow
// enough to catch a value typed in the wrong unit.
struct Plausible {
  body::Measurement measurement;
  double low;
  double high;
};

constexpr Plausible kPlausible[] = {
    {body::Measurement::kStature, 100, 250},        {body::Measurement::kWeight, 25, 300},
    {body::Measurement::kBustGirth, 50, 200},       {body::Measurement::kUnderbustGirth, 45, 180},
    {body::Measurement::kWaistGirth, 40, 200},      {body::Measurement::kHipGirth, 50, 200},
    {body::Measurement::kThighGirth, 25, 110},      {body::Measurement::kUpperArmGirth, 12, 70},
    {body::Measurement::kNeckGirth, 20, 70},        {body::Measurement::kInsideLeg, 40, 130},
    {body::Measurement::kArmLength, 30, 100},       {body::Measurement::kShoulderWidth, 20, 70},
    {body::Measurement::kNavelWaistGirth, 40, 200},
};

std::string FieldName(body::Measurement measurement) {
  return absl::StrCat(body::MeasurementName(measurement), "_", body::TypedUnit(measurement));
}

}  // namespace

double MeasurementAllowance(body::Measurement measurement) {
  switch (measurement) {
    case body::Measurement::kWeight:
      return 0.5;
    case body::Measurement::kStature:
    case body::Measurement::kNeckGirth:
    case body::Measurement::kUpperArmGirth:
      return 0.004;
    case body::Measurement::kInsideLeg:
    case body::Measurement::kArmLength:
    case body::Measurement::kShoulderWidth:
      return 0.005;
    default:
      return 0.009;
  }
}

absl::StatusOr<MeasurementSet> MeasurementsFromProto(const v1::TypedMeasurements& typed) {
  const google::protobuf::Descriptor* descriptor = typed.GetDescriptor();
  const google::protobuf::Reflection* reflection = typed.GetReflection();
  MeasurementSet set;
  for (const Plausible& range : kPlausible) {
    const std::string name = FieldName(range.measurement);
    const google::protobuf::FieldDescriptor* field = descriptor->FindFieldByName(name);
    if (field == nullptr) return absl::InternalError(absl::StrCat("no field ", name));
    if (!reflection->HasField(typed, field)) continue;
    const double value = reflection->GetDouble(typed, field);
    if (!std::isfinite(value)) {
      return absl::InvalidArgumentError(absl::StrCat(name, " is not a finite number"));
    }
    if (value < range.low || value > range.high) {
      return absl::InvalidArgumentError(absl::StrFormat(
          "%s is %g; an adult's is %g to %g %s", name, value, range.low, range.high,
          body::TypedUnit(range.measurement)));
    }
    set.emplace_back(range.measurement, value / body::InTypedUnit(range.measurement, 1.0));
  }
  if (set.empty()) return absl::InvalidArgumentError("no measurements given; stature_cm at least");
  if (std::none_of(set.begin(), set.end(), [](const auto& entry) {
        return entry.first == body::Measurement::kStature;
      })) {
    return absl::InvalidArgumentError("stature_cm is required");
  }
  return set;
}

v1::TypedMeasurements MeasurementsToProto(const body::BodyMeasurements& measurements) {
  v1::TypedMeasurements typed;
  const google::protobuf::Reflection* reflection = typed.GetReflection();
  for (body::Measurement m : body::AllMeasurements()) {
    const double value = measurements[static_cast<int>(m)];
    if (!std::isfinite(value)) continue;
    reflection->SetDouble(&typed, typed.GetDescriptor()->FindFieldByName(FieldName(m)),
                          body::InTypedUnit(m, value));
  }
  return typed;
}

absl::StatusOr<MeasurementModel> MeasurementModel::Build(const LoadedAvatarBasis& basis) {
  ASSIGN_OR_RETURN(core::Mesh mean, proto::MeshFromProto(basis.message.mean()));
  MeasurementModel model;
  model.triangles_ = core::Triangulate(mean.faces);
  model.topology_ = {.topology_id = std::move(mean.topology_id),
                     .positions = {},
                     .faces = std::move(mean.faces)};
  const int n = static_cast<int>(basis.pca.variances.size());
  const Eigen::VectorXd sigma = basis.pca.variances.cwiseSqrt();

  // Rows: [1, w] per sample; measured: every measurement per sample.
  Eigen::MatrixXd design(kModelSamples, n + 1);
  Eigen::MatrixXd measured(kModelSamples, body::kMeasurementCount);
  int rows = 0;
  for (int s = 0; s < kModelSamples; ++s) {
    core::Random random(kModelSeed, static_cast<uint64_t>(s));
    Eigen::VectorXd w(n);
    for (int k = 0; k < n; ++k) w(k) = sigma(k) * random.TruncatedNormal(0, 1, -3, 3);
    const Eigen::VectorXd x = core::ReconstructFromWeights(basis.pca, w);
    const core::Positions positions =
        Eigen::Map<const core::Positions>(x.data(), x.size() / 3, 3);
    const absl::StatusOr<body::BodyMeasurements> m =
        body::MeasureBody(positions, model.triangles_, body::AllMeasurements());
    if (!m.ok()) continue;  // A sampled body a landmark cannot be found on teaches nothing.
    design(rows, 0) = 1;
    design.row(rows).tail(n) = w.transpose();
    for (int i = 0; i < body::kMeasurementCount; ++i) measured(rows, i) = (*m)[i];
    ++rows;
  }
  if (rows < 2 * (n + 1)) {
    return absl::FailedPreconditionError(absl::StrCat(
        "avatar basis ", basis.message.id(), ": only ", rows, " of ", kModelSamples,
        " sampled bodies could be measured; is it a basis of ", body::kBodyTopologyId, "?"));
  }
  const Eigen::MatrixXd x = design.topRows(rows);
  const Eigen::MatrixXd y = measured.topRows(rows);
  const Eigen::MatrixXd beta = (x.transpose() * x).ldlt().solve(x.transpose() * y);
  model.mean_ = beta.row(0).transpose();
  model.response_ = beta.bottomRows(n).transpose();
  const Eigen::MatrixXd residual = y - x * beta;
  model.residual_sd_ =
      (residual.colwise().squaredNorm() / static_cast<double>(rows - n - 1)).cwiseSqrt().transpose();
  return model;
}

absl::StatusOr<MeasuredAvatar> AvatarFromMeasurements(const LoadedAvatarBasis& basis,
                                                      const MeasurementModel& model,
                                                      const MeasurementSet& given) {
  if (given.empty()) return absl::InvalidArgumentError("no measurements given");
  const int n = static_cast<int>(basis.pca.variances.size());
  const int s = static_cast<int>(given.size());
  std::vector<body::Measurement> which;
  Eigen::VectorXd target(s), allowance(s), noise(s), at_mean(s);
  Eigen::MatrixXd jacobian(s, n);
  for (int i = 0; i < s; ++i) {
    const int m = static_cast<int>(given[i].first);
    which.push_back(given[i].first);
    target(i) = given[i].second;
    allowance(i) = MeasurementAllowance(given[i].first);
    noise(i) = model.residual_sd()(m);
    at_mean(i) = model.mean()(m);
    jacobian.row(i) = model.response().row(m);
  }
  const Eigen::VectorXd variance = basis.pca.variances;

  // The conditional Gaussian of the weights given the measurements, under the linear model
  // m = at_mean + J w + e, e ~ N(0, diag(noise^2 + allowance^2)), w ~ N(0, diag(variance)).
  const Eigen::MatrixXd sigma_jt = variance.asDiagonal() * jacobian.transpose();
  Eigen::MatrixXd innovation = jacobian * sigma_jt;
  innovation.diagonal() += (noise.array().square() + allowance.array().square()).matrix();
  // The weights stay within the population's 4 sigma: beyond, the linear response
  // extrapolates into shapes no body has (150 cm with a 160 cm hip reached its hip at 7 sigma).
  const Eigen::VectorXd limit = kOutOfDistributionSigmas * variance.cwiseSqrt();
  Eigen::VectorXd w = (sigma_jt * innovation.ldlt().solve(target - at_mean))
                          .cwiseMax(-limit)
                          .cwiseMin(limit);

  // Gauss-Newton through the real measurement functions with the Mahalanobis prior: each
  // given measurement counts in units of half its allowance (below), each weight in units of
  // its sigma.
  // The Jacobian starts as the model's linear response and follows the real functions by
  // Broyden updates, one body measured per iteration.
  auto measure = [&](const Eigen::VectorXd& weights) -> absl::StatusOr<Eigen::VectorXd> {
    const Eigen::VectorXd x = core::ReconstructFromWeights(basis.pca, weights);
    const core::Positions positions =
        Eigen::Map<const core::Positions>(x.data(), x.size() / 3, 3);
    ASSIGN_OR_RETURN(const body::BodyMeasurements m,
                     body::MeasureBody(positions, model.triangles(), which));
    Eigen::VectorXd values(s);
    for (int i = 0; i < s; ++i) values(i) = m[static_cast<int>(which[i])];
    return values;
  };
  // Each measurement counts in units of half its allowance. Measured on 50 held-out women
  // given all 13 measurements: at the full allowance the prior holds 4.2% of them outside it
  // (surface error 9.0 mm); at a quarter the solve chases the measurements into shapes no
  // population body has (12.1 mm); at half, 1.4% outside and 8.9 mm.
  const Eigen::VectorXd precision = (0.5 * allowance).array().square().inverse();
  const Eigen::VectorXd prior = variance.array().inverse();
  auto energy = [&](const Eigen::VectorXd& weights, const Eigen::VectorXd& values) {
    return (values - target).cwiseProduct(values - target).dot(precision) +
           weights.cwiseProduct(weights).dot(prior);
  };
  ASSIGN_OR_RETURN(Eigen::VectorXd values, measure(w));
  double current = energy(w, values);
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    Eigen::MatrixXd normal = jacobian.transpose() * precision.asDiagonal() * jacobian;
    normal.diagonal() += prior;
    const Eigen::VectorXd gradient = jacobian.transpose() *
                                         precision.cwiseProduct(values - target) +
                                     prior.cwiseProduct(w);
    Eigen::VectorXd step =
        (w - normal.ldlt().solve(gradient)).cwiseMax(-limit).cwiseMin(limit) - w;
    bool improved = false;
    for (int halving = 0; halving < 4 && !improved; ++halving, step /= 2) {
      const Eigen::VectorXd next = w + step;
      absl::StatusOr<Eigen::VectorXd> next_values = measure(next);
      if (!next_values.ok()) continue;
      jacobian += ((*next_values - values) - jacobian * step) * step.transpose() /
                  step.squaredNorm();
      const double next_energy = energy(next, *next_values);
      if (next_energy < current) {
        w = next;
        values = *std::move(next_values);
        improved = current - next_energy > 1e-6 * current;
        current = next_energy;
        if (!improved) break;
      }
    }
    if (!improved) break;
  }

  MeasuredAvatar result;
  result.weights = w;
  const Eigen::VectorXd x = core::ReconstructFromWeights(basis.pca, w);
  result.avatar = model.topology();
  result.avatar.positions = Eigen::Map<const core::Positions>(x.data(), x.size() / 3, 3);
  for (int i = 0; i < s; ++i) {
    result.residuals.emplace_back(which[i], target(i), values(i));
    if (std::abs(values(i) - target(i)) > allowance(i)) {
      const absl::string_view unit = body::TypedUnit(which[i]);
      result.out_of_distribution_reasons.push_back(absl::StrFormat(
          "%s: %.1f %s given, the nearest body of the population has %.1f %s (allowance %.1f)",
          body::MeasurementName(which[i]), body::InTypedUnit(which[i], target(i)), unit,
          body::InTypedUnit(which[i], values(i)), unit,
          body::InTypedUnit(which[i], allowance(i))));
    }
  }
  for (int k = 0; k < n; ++k) {
    const double sigmas = std::abs(w(k)) / std::sqrt(variance(k));
    if (sigmas > kOutOfDistributionSigmas - 1e-6) {
      result.out_of_distribution_reasons.push_back(
          absl::StrFormat("component %d lies %.1f sigma from the mean", k, sigmas));
    }
  }
  return result;
}

}  // namespace fitbase::pipeline

namespace fitbase::pipeline {

absl::StatusOr<std::string> EvaluateAvatarFromMeasurements(
    const LoadedAvatarBasis& basis, const MeasurementModel& model,
    const std::vector<core::Mesh>& avatars) {
  using M = body::Measurement;
  struct InputSet {
    const char* name;
    std::vector<M> measurements;
  };
  const std::vector<InputSet> sets = {
      {"stature, weight", {M::kStature, M::kWeight}},
      {"+ bust, waist, hip", {M::kStature, M::kWeight, M::kBustGirth, M::kWaistGirth, M::kHipGirth}},
      {"all 13", {body::AllMeasurements().begin(), body::AllMeasurements().end()}},
  };
  std::string table = absl::StrFormat(
      "%d avatars, basis %s (%d components)\n\n| given | reproduced within allowance | "
      "worst measurement, avatars within | surface error mean mm | p95 mm | flagged OOD |\n|---|---|---|---|---|---|\n",
      avatars.size(), basis.message.id().substr(0, 12), basis.pca.variances.size());
  for (const InputSet& set : sets) {
    int within = 0, total = 0, flagged = 0;
    std::array<int, body::kMeasurementCount> missed{};
    std::vector<double> errors;
    double sum = 0;
    for (const core::Mesh& avatar : avatars) {
      ASSIGN_OR_RETURN(const body::BodyMeasurements truth,
                       body::MeasureBody(avatar.positions, model.triangles(), set.measurements));
      MeasurementSet given;
      for (M m : set.measurements) given.emplace_back(m, truth[static_cast<int>(m)]);
      ASSIGN_OR_RETURN(const MeasuredAvatar made, AvatarFromMeasurements(basis, model, given));
      for (const auto& [m, value, reached] : made.residuals) {
        ++total;
        if (std::abs(reached - value) <= MeasurementAllowance(m)) {
          ++within;
        } else {
          ++missed[static_cast<int>(m)];
        }
      }
      flagged += !made.out_of_distribution_reasons.empty();
      const Eigen::VectorXd distance =
          (made.avatar.positions - avatar.positions).rowwise().norm() * 1e3;
      sum += distance.mean();
      errors.insert(errors.end(), distance.data(), distance.data() + distance.size());
    }
    std::sort(errors.begin(), errors.end());
    const int worst = static_cast<int>(std::max_element(missed.begin(), missed.end()) -
                                       missed.begin());
    absl::StrAppendFormat(
        &table, "| %s | %.1f%% | %s %.0f%% | %.1f | %.1f | %d |\n", set.name,
        100.0 * within / std::max(total, 1), body::MeasurementName(static_cast<M>(worst)),
        100.0 * (1.0 - missed[worst] / static_cast<double>(avatars.size())),
        sum / static_cast<double>(avatars.size()),
        errors.empty() ? 0.0 : errors[static_cast<size_t>(0.95 * (errors.size() - 1))], flagged);
  }
  return table;
}

}  // namespace fitbase::pipeline
