#ifndef FITBASE_CORE_CLOTHING_MODEL_H_
#define FITBASE_CORE_CLOTHING_MODEL_H_

#include <cstdint>
#include <string>
#include <vector>

#include "Eigen/Core"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace fitbase::core {

// How a garment's fit follows the avatar weights (Gillies, Ballin & Csaji 2004, and two
// finite-difference models of the drape around the mean avatar).
enum class ClothingMethod {
  kPaper,      // The published method: clothing mean and normalized clothing components.
  kLinear,     // g0 + sum_k w_k (g_k+ - g_k-) / (2 s sigma_k).
  kQuadratic,  // linear + sum_k w_k^2 (g_k+ + g_k- - 2 g0) / (2 s^2 sigma_k^2).
};

absl::StatusOr<ClothingMethod> ParseClothingMethod(absl::string_view name);
std::string ClothingMethodName(ClothingMethod method);

// The example avatars of a clothing basis, in avatar-basis weights (m): index 0 is the mean
// avatar, 1..N are mu + s sigma_k phi_k and N+1..2N are mu - s sigma_k phi_k (k = index - 1
// and index - N - 1). Every method draws on these 2N + 1; `paper` uses the N `+` ones.
struct ExampleDesign {
  double scale = 1.0;        // s.
  Eigen::VectorXd sigmas;    // N, sigma_k = sqrt(variance_k), m.
  int component_count() const { return static_cast<int>(sigmas.size()); }
  int example_count() const { return 2 * component_count() + 1; }
  Eigen::VectorXd Weights(int example) const;  // N.
  std::string Label(int example) const;        // "mean", "+1", "-1", ... (components from 1).
};

// ExampleDesign for sigmas > 0 (finite) and scale > 0 (finite); InvalidArgument otherwise.
absl::StatusOr<ExampleDesign> MakeExampleDesign(const Eigen::VectorXd& sigmas, double scale);

// g(w) = mean + terms * f(w), f_t(w) = w[term_component[t]] ^ term_power[t].
// Flattened garments: D = 3V floats, xyz interleaved, meters. `basis` is D x (1 + T),
// column-major: column 0 is the mean and column 1 + t is term t, each one contiguous D-vector.
// A fit is then one matrix-vector product with (1, f(w)) and a batch of customers one matrix
// product, each result written once (bench/fit_bench measures this layout fastest).
struct ClothingModel {
  ClothingMethod method = ClothingMethod::kLinear;
  int component_count = 0;  // N: the length of the weight vectors the fit takes.
  Eigen::MatrixXf basis;    // D x (1 + T).
  std::vector<int32_t> term_component;  // T, in [0, N).
  std::vector<int32_t> term_power;      // T, 1 or 2.
  auto mean() const { return basis.col(0); }
  auto terms() const { return basis.rightCols(basis.cols() - 1); }
  int64_t term_count() const { return basis.cols() - 1; }
  int64_t vertex_count() const { return basis.rows() / 3; }
};

// drapes: D x (2N + 1), the example drapes in ExampleDesign order, meters, all finite.
// InvalidArgument for a shape that does not match the design or non-finite values.
absl::StatusOr<ClothingModel> BuildClothingModel(ClothingMethod method,
                                                 const ExampleDesign& design,
                                                 const Eigen::MatrixXd& drapes);

// Checks a model read from elsewhere: sizes agree, indices and powers in range, all finite.
absl::Status ValidateClothingModel(const ClothingModel& model);

// weights must have model.component_count finite entries (InvalidArgument otherwise).
absl::Status CheckFitWeights(const ClothingModel& model, const Eigen::VectorXf& weights);

// One customer: out (D) = g(weights). `features` is scratch of 1 + T floats. No allocation once
// `out` and `features` have their sizes; the weights are assumed checked.
void FitClothing(const ClothingModel& model, const Eigen::VectorXf& weights,
                 Eigen::VectorXf& features, Eigen::VectorXf& out);

// Many customers as one matrix product: weights N x B, out D x B.
void FitClothingBatch(const ClothingModel& model, const Eigen::MatrixXf& weights,
                      Eigen::MatrixXf& out);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_CLOTHING_MODEL_H_
