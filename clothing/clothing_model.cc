#include "clothing/clothing_model.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "Eigen/Cholesky"
#include "Eigen/Eigenvalues"
#include "absl/strings/str_cat.h"
#include "core/kernel_ridge.h"
#include "core/matrix_vector.h"
#include "core/parallel_for.h"
#include "core/status_macros.h"

namespace fitbase::clothing {

absl::StatusOr<ClothingMethod> ParseClothingMethod(absl::string_view name) {
  if (name == "paper") return ClothingMethod::kPaper;
  if (name == "linear") return ClothingMethod::kLinear;
  if (name == "quadratic") return ClothingMethod::kQuadratic;
  if (name == "kernel") return ClothingMethod::kKernel;
  return absl::InvalidArgumentError(absl::StrCat(
      "unknown clothing method '", name, "'; expected paper, linear, quadratic or kernel"));
}

std::string ClothingMethodName(ClothingMethod method) {
  switch (method) {
    case ClothingMethod::kPaper:
      return "paper";
    case ClothingMethod::kLinear:
      return "linear";
    case ClothingMethod::kQuadratic:
      return "quadratic";
    case ClothingMethod::kKernel:
      return "kernel";
  }
  return "unknown";
}

Eigen::VectorXd ExampleDesign::Weights(int example) const {
  const int n = component_count();
  Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
  if (example >= 1 && example <= n) w(example - 1) = scale * sigmas(example - 1);
  if (example > n) w(example - n - 1) = -scale * sigmas(example - n - 1);
  return w;
}

std::string ExampleDesign::Label(int example) const {
  const int n = component_count();
  if (example == 0) return "mean";
  return example <= n ? absl::StrCat("+", example) : absl::StrCat("-", example - n);
}

absl::StatusOr<ExampleDesign> MakeExampleDesign(const Eigen::VectorXd& sigmas, double scale) {
  if (!std::isfinite(scale) || scale <= 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("example scale must be positive and finite, got ", scale));
  }
  if (sigmas.size() == 0) return absl::InvalidArgumentError("the avatar basis has no components");
  for (int k = 0; k < sigmas.size(); ++k) {
    if (!std::isfinite(sigmas(k)) || sigmas(k) <= 0) {
      return absl::InvalidArgumentError(
          absl::StrCat("component ", k + 1, " has sigma ", sigmas(k), "; expected > 0"));
    }
  }
  return ExampleDesign{scale, sigmas};
}

namespace {

void AddTerms(const Eigen::MatrixXd& columns, int power, ClothingModel& model) {
  const Eigen::Index first = model.basis.cols();
  model.basis.conservativeResize(columns.rows(), first + columns.cols());
  model.basis.rightCols(columns.cols()) = columns.cast<float>();
  for (Eigen::Index k = 0; k < columns.cols(); ++k) {
    model.term_component.push_back(static_cast<int32_t>(k));
    model.term_power.push_back(power);
  }
}

// The published model: the N fitted examples mu + s sigma_k phi_k, their mean as the clothing
// mean, and each example minus that mean, normalized, as clothing component k, to be weighted
// directly by the avatar weight w_k. With unit-length avatar components this maps a unit step
// along phi_k to a unit-length garment change, whatever the garment's actual response.
Eigen::MatrixXd PaperComponents(const Eigen::MatrixXd& plus, Eigen::VectorXd& mean) {
  mean = plus.rowwise().mean();
  Eigen::MatrixXd components = plus.colwise() - mean;
  for (Eigen::Index k = 0; k < components.cols(); ++k) {
    const double norm = components.col(k).norm();
    if (norm > 0) components.col(k) /= norm;
  }
  return components;
}

}  // namespace

absl::StatusOr<ClothingModel> BuildClothingModel(ClothingMethod method,
                                                 const ExampleDesign& design,
                                                 const Eigen::MatrixXd& drapes) {
  const int n = design.component_count();
  if (drapes.cols() != design.example_count() || drapes.rows() == 0 || drapes.rows() % 3 != 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "example drapes are ", drapes.rows(), " x ", drapes.cols(), "; expected 3V x ",
        design.example_count(), " (2N + 1 examples for N = ", n, ")"));
  }
  if (!drapes.allFinite()) return absl::InvalidArgumentError("example drapes are not finite");
  if (method == ClothingMethod::kKernel) {
    return absl::InvalidArgumentError(
        "the kernel method learns from drapes of sampled bodies; build it with "
        "BuildKernelClothingModel");
  }
  ClothingModel model;
  model.method = method;
  model.component_count = n;
  model.basis.resize(drapes.rows(), 1);
  const Eigen::MatrixXd plus = drapes.middleCols(1, n);
  const Eigen::MatrixXd minus = drapes.middleCols(n + 1, n);
  const Eigen::VectorXd g0 = drapes.col(0);
  if (method == ClothingMethod::kPaper) {
    Eigen::VectorXd mean;
    const Eigen::MatrixXd components = PaperComponents(plus, mean);
    model.basis.col(0) = mean.cast<float>();
    AddTerms(components, 1, model);
    return model;
  }
  model.basis.col(0) = g0.cast<float>();
  const Eigen::ArrayXd step = design.scale * design.sigmas.array();
  AddTerms((plus - minus) * (0.5 / step).matrix().asDiagonal(), 1, model);
  if (method == ClothingMethod::kQuadratic) {
    AddTerms(((plus + minus).colwise() - 2 * g0) * (0.5 / step.square()).matrix().asDiagonal(),
             2, model);
  }
  return model;
}

namespace {

struct ChosenKernel {
  core::KernelRidge ridge;
  Eigen::ArrayXd scale;  // N: z = w .* scale.
  std::string scaling;   // KernelBuildReport::input_scaling.
};

// The kernel of one shape with the lowest leave-one-out error over the training bodies
// (weights: N x M) and their misses (targets: M x C), as BuildKernelClothingModel describes,
// with a reach per component if `relevance`; nullopt if the bodies do not differ under either
// scaling.
std::optional<ChosenKernel> ChooseKernel(core::KernelShape shape, const Eigen::MatrixXd& weights,
                                         const Eigen::MatrixXd& targets,
                                         const Eigen::ArrayXd& sigma_scale,
                                         const Eigen::ArrayXd& response_scale, bool relevance) {
  std::optional<ChosenKernel> best;
  for (const auto& [name, scale] :
       {std::pair<const char*, const Eigen::ArrayXd*>{"sigma", &sigma_scale},
        std::pair<const char*, const Eigen::ArrayXd*>{"response", &response_scale}}) {
    absl::StatusOr<core::KernelRidge> fitted = core::FitKernelRidge(
        scale->matrix().asDiagonal() * weights, targets, {.shape = shape});
    if (!fitted.ok()) continue;  // All inputs equal under this scaling: try the other.
    if (!best || fitted->loo_rms < best->ridge.loo_rms) {
      best = ChosenKernel{*std::move(fitted), *scale, name};
    }
  }
  if (!best) return std::nullopt;
  // One reach per component, from the better scaling: the linear model's misses follow a few
  // components closely and most others loosely or not at all, which one length scale for all
  // cannot say. A scaling with a zero (a component the linear model does not move the garment
  // by) is not searched.
  if (relevance) {
    absl::StatusOr<core::RelevanceFit> relevance = core::FitKernelRidgeRelevance(
        weights, targets, best->scale.matrix() / best->ridge.length_scale, {.shape = shape});
    if (relevance.ok() && relevance->model.loo_rms < best->ridge.loo_rms) {
      best = ChosenKernel{std::move(relevance->model), relevance->scales.array(), "relevance"};
    }
  }
  return best;
}

}  // namespace

absl::StatusOr<ClothingModel> BuildKernelClothingModel(const ExampleDesign& design,
                                                       const Eigen::MatrixXd& drapes,
                                                       const SampledDrapes& samples,
                                                       const KernelBuildOptions& options,
                                                       KernelBuildReport* report) {
  const int n = design.component_count();
  const Eigen::Index sampled = samples.weights.cols();
  if (samples.weights.rows() != n || sampled < 1 || samples.drapes.cols() != sampled ||
      samples.drapes.rows() != drapes.rows()) {
    return absl::InvalidArgumentError(absl::StrCat(
        "sampled drapes are ", samples.drapes.rows(), " x ", samples.drapes.cols(),
        " with weights ", samples.weights.rows(), " x ", sampled, "; expected ", drapes.rows(),
        " x M and ", n, " x M, M >= 1"));
  }
  if (!samples.weights.allFinite() || !samples.drapes.allFinite()) {
    return absl::InvalidArgumentError("sampled drapes or their weights are not finite");
  }
  if (!(options.output_energy > 0 && options.output_energy <= 1) || options.max_outputs < 1) {
    return absl::InvalidArgumentError("kernel outputs need an energy in (0, 1] and a count >= 1");
  }
  if (options.shapes.empty()) return absl::InvalidArgumentError("no kernel shape to choose from");
  if (options.threads < 1) {
    return absl::InvalidArgumentError(
        absl::StrCat("kernel shapes need at least one thread; got ", options.threads));
  }
  if (options.search_bodies < 2) {
    return absl::InvalidArgumentError(absl::StrCat(
        "the kernel's search needs at least 2 training bodies; got ", options.search_bodies));
  }
  ASSIGN_OR_RETURN(ClothingModel model,
                   BuildClothingModel(ClothingMethod::kLinear, design, drapes));
  model.method = ClothingMethod::kKernel;
  const Eigen::Index d = drapes.rows();
  const Eigen::Index examples = design.example_count();
  const Eigen::Index m = examples + sampled;
  const double vertices = static_cast<double>(d / 3);

  // Every body with a drape trains the correction: the axis examples (where the linear model
  // misses by its curvature) and the sampled bodies.
  Eigen::MatrixXd features(1 + n, m);
  features.row(0).setOnes();
  for (Eigen::Index e = 0; e < examples; ++e) {
    features.col(e).tail(n) = design.Weights(static_cast<int>(e));
  }
  features.bottomRightCorner(n, sampled) = samples.weights;
  Eigen::MatrixXd misses(d, m);
  misses.leftCols(examples) = drapes;
  misses.rightCols(sampled) = samples.drapes;
  const bool least_squares = m >= kLeastSquaresBodiesPerComponent * n;
  if (least_squares) {
    // The mean and the N slopes that miss the training drapes least: (F F^T) B^T = F Y^T, F the
    // (1 + N) x M features, Y the D x M drapes. The axis examples alone span every component
    // (at +-s sigma_k, sigma_k > 0), so the (1 + N) x (1 + N) F F^T is positive definite.
    const Eigen::LLT<Eigen::MatrixXd> normal(features * features.transpose());
    model.basis.leftCols(1 + n) =
        normal.solve(features * misses.transpose()).transpose().cast<float>();
  }
  misses.noalias() -= model.basis.cast<double>() * features;

  // The misses' principal directions, from the M x M Gram matrix (M is far below D).
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> gram(misses.transpose() * misses);
  const Eigen::VectorXd energies = gram.eigenvalues().reverse().cwiseMax(0.0);
  const double total = energies.sum();
  int outputs = 0;
  double kept = 0;
  while (total > 0 && outputs < options.max_outputs && outputs < m &&
         kept < options.output_energy * total && energies(outputs) > 0) {
    kept += energies(outputs++);
  }
  const Eigen::MatrixXd directions_in_samples = gram.eigenvectors().rowwise().reverse();
  Eigen::MatrixXd directions(d, outputs);  // Orthonormal columns.
  Eigen::MatrixXd targets(m, outputs);     // Each body's miss in those directions.
  for (int c = 0; c < outputs; ++c) {
    const double s = std::sqrt(energies(c));
    directions.col(c) = misses * directions_in_samples.col(c) / s;
    targets.col(c) = directions_in_samples.col(c) * s;
  }
  const double linear_rms = std::sqrt(total / (static_cast<double>(m) * vertices));

  const Eigen::ArrayXd sigma_scale = design.sigmas.array().inverse();
  Eigen::ArrayXd response_scale(n);
  for (int k = 0; k < n; ++k) {
    response_scale(k) = model.basis.col(1 + k).cast<double>().norm() / std::sqrt(vertices);
  }
  KernelBuildReport chosen;
  chosen.linear_part = least_squares ? "least-squares" : "axis";
  chosen.outputs = outputs;
  chosen.kept_energy = total > 0 ? kept / total : 1.0;
  chosen.linear_rms_mm = 1000 * linear_rms;
  chosen.loo_rms_mm = chosen.linear_rms_mm;
  chosen.searched_bodies = m;
  if (outputs > 0) {
    // The kernel's shape is chosen like its reaches, by the leave-one-out error, and only where
    // the reaches are (KernelBuildOptions::shapes says why): where the searched bodies number
    // kRelevanceBodiesPerComponent per component.
    const Eigen::MatrixXd weights = features.bottomRows(n);
    const Eigen::Index search = std::min<Eigen::Index>(m, options.search_bodies);
    const bool relevance = search >= kRelevanceBodiesPerComponent * n;
    const size_t searched = relevance ? options.shapes.size() : 1;
    std::vector<std::optional<ChosenKernel>> fitted(searched);
    core::ParallelFor(searched, options.threads, [&](size_t i) {
      fitted[i] = ChooseKernel(options.shapes[i], weights.leftCols(search), targets.topRows(search),
                               sigma_scale, response_scale, relevance);
    });
    // In the shapes' order, whichever thread searched them: the same choice for any count.
    std::optional<ChosenKernel> best;
    for (std::optional<ChosenKernel>& shape : fitted) {
      if (shape && (!best || shape->ridge.loo_rms < best->ridge.loo_rms)) best = std::move(shape);
    }
    if (!best) {
      return absl::InvalidArgumentError("the sampled bodies do not differ in their weights");
    }
    if (search < m) {
      chosen.searched_bodies = search;
      // The reaches found on the first bodies, z = scale .* w / l, and the ridge and
      // coefficients from all of them.
      ASSIGN_OR_RETURN(core::RelevanceFit all,
                       core::FitKernelRidgeRelevance(
                           weights, targets, best->scale.matrix() / best->ridge.length_scale,
                           {.shape = best->ridge.shape, .sweeps = 0}));
      best = ChosenKernel{std::move(all.model), all.scales.array(), best->scaling};
    }
    chosen.input_scaling = best->scaling;
    chosen.shape = core::KernelShapeName(best->ridge.shape);
    const double discarded = std::max(0.0, total - kept);
    const core::KernelRidge& ridge = best->ridge;
    chosen.length_scale = ridge.length_scale;
    chosen.ridge = ridge.ridge;
    chosen.loo_rms_mm =
        1000 * std::sqrt((ridge.loo_rms * ridge.loo_rms * static_cast<double>(m) + discarded) /
                         (static_cast<double>(m) * vertices));
    model.kernel.shape = ridge.shape;
    model.kernel.length_scale = static_cast<float>(ridge.length_scale);
    model.kernel.input_scale = best->scale.cast<float>();
    model.kernel.centers = ridge.centers.cast<float>();
    model.kernel.coefficients = ridge.coefficients.cast<float>();
    const Eigen::Index first = model.basis.cols();
    model.basis.conservativeResize(d, first + outputs);
    model.basis.rightCols(outputs) = directions.cast<float>();
  } else {
    model.kernel.input_scale = sigma_scale.cast<float>();
    model.kernel.centers.resize(n, 0);
    model.kernel.coefficients.resize(0, 0);
  }
  if (report != nullptr) *report = chosen;
  return model;
}

absl::Status ValidateClothingModel(const ClothingModel& model) {
  const Eigen::Index d = model.basis.rows();
  const Eigen::Index t = model.term_count();
  if (d == 0 || d % 3 != 0) {
    return absl::InvalidArgumentError(absl::StrCat("clothing mean has ", d, " values; expected 3V"));
  }
  if (model.component_count <= 0) {
    return absl::InvalidArgumentError("clothing model takes no avatar weights");
  }
  const KernelCorrection& kernel = model.kernel;
  const Eigen::Index c = kernel.output_count();
  if (model.basis.cols() != 1 + t + c ||
      static_cast<Eigen::Index>(model.term_power.size()) != t) {
    return absl::InvalidArgumentError(absl::StrCat(
        "clothing model has ", model.basis.cols(), " columns for ", t, " terms (",
        model.term_power.size(), " powers) and ", c, " kernel outputs"));
  }
  if (model.method == ClothingMethod::kKernel) {
    if (kernel.input_scale.size() != model.component_count ||
        kernel.centers.rows() != model.component_count ||
        kernel.coefficients.cols() != kernel.center_count()) {
      return absl::InvalidArgumentError(absl::StrCat(
          "kernel correction has ", kernel.input_scale.size(), " input scales, centers ",
          kernel.centers.rows(), " x ", kernel.centers.cols(), " and coefficients ", c, " x ",
          kernel.coefficients.cols(), " for ", model.component_count, " components"));
    }
    if (!std::isfinite(kernel.length_scale) || !(kernel.length_scale > 0) ||
        !kernel.input_scale.allFinite() || !kernel.centers.allFinite() ||
        !kernel.coefficients.allFinite()) {
      return absl::InvalidArgumentError("kernel correction is not finite or its length scale <= 0");
    }
  } else if (c != 0 || kernel.center_count() != 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "a ", ClothingMethodName(model.method), " clothing model has no kernel correction"));
  }
  for (Eigen::Index i = 0; i < t; ++i) {
    if (model.term_component[i] < 0 || model.term_component[i] >= model.component_count) {
      return absl::InvalidArgumentError(absl::StrCat("clothing term ", i, " uses component ",
                                                     model.term_component[i], " of ",
                                                     model.component_count));
    }
    if (model.term_power[i] != 1 && model.term_power[i] != 2) {
      return absl::InvalidArgumentError(
          absl::StrCat("clothing term ", i, " has power ", model.term_power[i]));
    }
  }
  if (!model.basis.allFinite()) {
    return absl::InvalidArgumentError("clothing model is not finite");
  }
  return absl::OkStatus();
}

absl::Status CheckFitWeights(const ClothingModel& model, const Eigen::VectorXf& weights) {
  if (weights.size() != model.component_count) {
    return absl::InvalidArgumentError(absl::StrCat("got ", weights.size(),
                                                   " avatar weights; the clothing basis takes ",
                                                   model.component_count));
  }
  if (!weights.allFinite()) return absl::InvalidArgumentError("avatar weights are not finite");
  return absl::OkStatus();
}

namespace {

// (1, f_0(w), ..., f_T-1(w), c_0(w), ..., c_C-1(w)): the mean's coefficient first.
template <typename Weights, typename Features>
void ComputeFeatures(const ClothingModel& model, const Weights& weights, Features& features) {
  features(0) = 1;
  for (size_t t = 0; t < model.term_component.size(); ++t) {
    const auto w = weights(model.term_component[t]);
    features(static_cast<Eigen::Index>(t) + 1) = model.term_power[t] == 1 ? w : w * w;
  }
  const KernelCorrection& kernel = model.kernel;
  const Eigen::Index c = kernel.output_count();
  if (c == 0) return;
  auto outputs = features.tail(c);
  outputs.setZero();
  const Eigen::Index n = kernel.centers.rows();
  const auto squared_distance = [&](Eigen::Index j) {
    float squared = 0;
    for (Eigen::Index k = 0; k < n; ++k) {
      const float delta = weights(k) * kernel.input_scale(k) - kernel.centers(k, j);
      squared += delta * delta;
    }
    return squared;
  };
  // The Gaussian keeps the arithmetic it had before there were shapes: older bases fit to the
  // same bytes.
  if (kernel.shape == core::KernelShape::kGaussian) {
    const float scale = -0.5f / (kernel.length_scale * kernel.length_scale);
    for (Eigen::Index j = 0; j < kernel.center_count(); ++j) {
      outputs += std::exp(scale * squared_distance(j)) * kernel.coefficients.col(j);
    }
    return;
  }
  const float inverse_l2 = 1.0f / (kernel.length_scale * kernel.length_scale);
  for (Eigen::Index j = 0; j < kernel.center_count(); ++j) {
    outputs += core::KernelOfScaledSquared(kernel.shape, squared_distance(j) * inverse_l2) *
               kernel.coefficients.col(j);
  }
}

}  // namespace

void ClothingFeatures(const ClothingModel& model, const Eigen::VectorXf& weights,
                      Eigen::VectorXf& features) {
  features.resize(1 + model.term_count() + model.kernel.output_count());
  ComputeFeatures(model, weights, features);
}

void FitClothing(const ClothingModel& model, const Eigen::VectorXf& weights,
                 Eigen::VectorXf& features, Eigen::VectorXf& out) {
  ClothingFeatures(model, weights, features);
  out.setZero(model.basis.rows());
  core::MultiplyAccumulate(model.basis, features, out);
}

void FitClothingBatch(const ClothingModel& model, const Eigen::MatrixXf& weights,
                      Eigen::MatrixXf& out) {
  Eigen::MatrixXf features(model.basis.cols(), weights.cols());
  for (Eigen::Index b = 0; b < weights.cols(); ++b) {
    auto column = features.col(b);
    ComputeFeatures(model, weights.col(b), column);
  }
  out.noalias() = model.basis * features;
}

}  // namespace fitbase::clothing
