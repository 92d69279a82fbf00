#include "core/clothing_model.h"

#include <cmath>

#include "absl/strings/str_cat.h"

namespace fitbase::core {

absl::StatusOr<ClothingMethod> ParseClothingMethod(absl::string_view name) {
  if (name == "paper") return ClothingMethod::kPaper;
  if (name == "linear") return ClothingMethod::kLinear;
  if (name == "quadratic") return ClothingMethod::kQuadratic;
  return absl::InvalidArgumentError(
      absl::StrCat("unknown clothing method '", name, "'; expected paper, linear or quadratic"));
}

std::string ClothingMethodName(ClothingMethod method) {
  switch (method) {
    case ClothingMethod::kPaper:
      return "paper";
    case ClothingMethod::kLinear:
      return "linear";
    case ClothingMethod::kQuadratic:
      return "quadratic";
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

absl::Status ValidateClothingModel(const ClothingModel& model) {
  const Eigen::Index d = model.basis.rows();
  const Eigen::Index t = model.term_count();
  if (d == 0 || d % 3 != 0) {
    return absl::InvalidArgumentError(absl::StrCat("clothing mean has ", d, " values; expected 3V"));
  }
  if (model.component_count <= 0) {
    return absl::InvalidArgumentError("clothing model takes no avatar weights");
  }
  if (t < 0) return absl::InvalidArgumentError("clothing model has no mean");
  if (static_cast<Eigen::Index>(model.term_component.size()) != t ||
      static_cast<Eigen::Index>(model.term_power.size()) != t) {
    return absl::InvalidArgumentError("clothing term components and powers disagree with terms");
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

// (1, f_0(w), ..., f_T-1(w)): the mean's coefficient first.
template <typename Weights, typename Features>
void ComputeFeatures(const ClothingModel& model, const Weights& weights, Features& features) {
  features(0) = 1;
  for (size_t t = 0; t < model.term_component.size(); ++t) {
    const auto w = weights(model.term_component[t]);
    features(static_cast<Eigen::Index>(t) + 1) = model.term_power[t] == 1 ? w : w * w;
  }
}

}  // namespace

void FitClothing(const ClothingModel& model, const Eigen::VectorXf& weights,
                 Eigen::VectorXf& features, Eigen::VectorXf& out) {
  features.resize(model.basis.cols());
  ComputeFeatures(model, weights, features);
  out.noalias() = model.basis * features;
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

}  // namespace fitbase::core
