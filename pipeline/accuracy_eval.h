#ifndef FITBASE_PIPELINE_ACCURACY_EVAL_H_
#define FITBASE_PIPELINE_ACCURACY_EVAL_H_

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "body/body_model.h"
#include "fitbase/v1/accuracy_report.pb.h"
#include "fitbase/v1/avatar_basis.pb.h"
#include "fitbase/v1/garment.pb.h"
#include "pipeline/drape_runner.h"
#include "workers/cloth_solver.h"
#include "workers/drape.h"

namespace fitbase::pipeline {

// A method of the eval that is no fit: each held-out avatar's drape on its body of the weights
// (mean + Phi w), measured against the drape on its own mesh. A fit from the weights cannot
// see what the projection leaves out of the body, so even a perfect model of the drape as a
// function of the weights misses by about this much.
inline constexpr char kWeightsDrape[] = "weights-drape";

struct AccuracyEvalSpec {
  const v1::AvatarBasis* avatar_basis = nullptr;
  std::vector<const v1::Garment*> garments;  // Each imported on avatar_basis.
  std::string size = "M";
  int holdout_count = 20;
  uint64_t holdout_seed = 2;
  std::string preset;  // Empty: the basis's own population preset.
  // The ground truth draped on each held-out avatar's body of the weights (mean + Phi w, the
  // body the fit is made for) instead of its own mesh, and penetration measured against that
  // body: the error without the projection's part.
  bool truth_on_weights_body = false;
  // The model rows fit each held-out avatar's own mesh (ClothingFitter::FitToBody) and are
  // shown on it, instead of the body of the weights. Not with truth_on_weights_body.
  bool fit_on_own_body = false;
  // Any of paper, linear, quadratic, kernel (needs sampled_drapes), nearest, geometric,
  // kWeightsDrape (not with truth_on_weights_body).
  std::vector<std::string> methods = {"paper", "linear", "quadratic", "nearest", "geometric"};
  double example_scale = 1.0;
  int sampled_drapes = 0;  // Per garment, for `kernel` (see ClothingBuildSpec).
  uint64_t sample_seed = 1;
  workers::ClothSettings settings;
  workers::DrapeSchedule schedule;
  DrapeRunOptions run;
  // Where the clothing bases are written as <garment>-<size>-<method>.fbc (empty: nowhere).
  std::filesystem::path clothing_dir;
};

// Drapes the held-out avatars (ground truth) and every garment's example avatars, builds the
// clothing bases, fits every held-out avatar with every method, and measures the per-vertex
// error against the drape, the penetration of the real held-out body, and the fit time.
// Errors: unknown method or preset, a garment of another basis, a failed drape.
absl::StatusOr<v1::AccuracyReport> EvaluateAccuracy(const body::BodyModel& body_model,
                                                    const AccuracyEvalSpec& spec);

// The report as a Markdown table per garment and overall.
std::string AccuracyReportMarkdown(const v1::AccuracyReport& report);

// Size advice from the fast fit against size advice from the drape. For each held-out body,
// every size of every garment is draped onto the body itself and judged on that body (the
// truth), and fitted from the body's weights (linear, with the clean-up) and judged on the
// body of the weights, as the fit service does. spec.size is unused; `sizes` are judged
// together (e.g. S, M, L, XL) and must be sizes of every garment.
struct AdviceAgreement {
  std::string garment_name;
  int bodies = 0;
  int same_size = 0;      // The fast fit recommends the drape's size.
  int within_one = 0;     // ... or a neighbouring size.
  std::map<std::string, int> drape_recommends;  // How often the drape recommends each size.
  // Mean |ease from the fit - ease from the drape| per region over sizes and bodies, cm.
  std::map<std::string, double> ease_gap_cm;
};
absl::StatusOr<std::vector<AdviceAgreement>> EvaluateAdviceAgreement(
    const body::BodyModel& body_model, const AccuracyEvalSpec& spec,
    const std::vector<std::string>& sizes);
std::string AdviceAgreementMarkdown(const std::vector<AdviceAgreement>& rows,
                                    const std::vector<std::string>& sizes,
                                    const AccuracyEvalSpec& spec);

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_ACCURACY_EVAL_H_
