#include "pipeline/accuracy_eval.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "body/population_calibration.h"
#include "body/population_sampler.h"
#include "clothing/clothing_fitter.h"
#include "core/pca_basis.h"
#include "core/status_macros.h"
#include "core/triangle_bvh.h"
#include "pipeline/avatar_projection.h"
#include "pipeline/clothing_basis_builder.h"
#include "pipeline/size_advisor.h"
#include "pipeline/skin_visibility.h"
#include "proto/avatar_basis_codec.h"
#include "proto/clothing_basis_codec.h"
#include "proto/mesh_codec.h"
#include "proto/message_file.h"
#include "workers/garment_drape.h"

namespace fitbase::pipeline {
namespace {

using Positions32 = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;

constexpr double kPenetrationSearch = 0.01;  // m: deeper than any fit's penetration.

// A held-out customer: the real body, its surface for penetration queries, its weights, and
// the body of the weights (mean + components x weights), which the fit service shows a fitted
// garment on.
struct Holdout {
  core::Positions body;
  core::TriangleBvh surface;
  Eigen::VectorXf weights;
  core::Positions weights_body;
  std::vector<float> body_xyz;  // body as 3B floats, xyz interleaved, for FitToBody.
};

// One row of the table, accumulated over avatars (and, for the overall table, garments).
struct RowStats {
  std::string method;
  bool cleanup = false;
  std::vector<float> errors_mm;
  // Per held-out avatar, over every garment the row takes in: its vertices' errors summed and
  // counted, for the standard error of the mean over avatars, and its pixels of visible skin.
  struct AvatarErrors {
    double sum_mm = 0;
    int64_t vertices = 0;
    SkinVisibility skin;
  };
  std::vector<AvatarErrors> avatars;
  int64_t below_0mm = 0;
  int64_t below_1mm = 0;
  double fit_micros_sum = 0;
  int fit_micros_count = 0;
  SkinVisibility skin;
  double skin_share_max = 0;
  double inside_share_max = 0;
  double edge_retreat_sum_mm = 0;
  int64_t edge_vertex_count = 0;

  // The fit of held-out avatar `avatar` against its drape `truth`.
  void Add(size_t avatar, const core::Positions& fit, const core::Positions& truth,
           const core::TriangleBvh& body, const GarmentEdges& edges) {
    if (avatars.size() <= avatar) avatars.resize(avatar + 1);
    for (Eigen::Index v = 0; v < fit.rows(); ++v) {
      errors_mm.push_back(static_cast<float>(1000 * (fit.row(v) - truth.row(v)).norm()));
      avatars[avatar].sum_mm += errors_mm.back();
      ++avatars[avatar].vertices;
      const core::SurfacePoint p = body.Closest(fit.row(v).transpose(), kPenetrationSearch);
      below_0mm += p.found && p.signed_distance < 0;
      below_1mm += p.found && p.signed_distance < 0.001;
    }
    const Eigen::VectorXd retreat = EdgeRetreat(edges, truth, fit);
    for (const double r : retreat) {
      if (std::isnan(r)) continue;
      edge_retreat_sum_mm += 1000 * r;
      ++edge_vertex_count;
    }
  }

  // The fit of held-out avatar `avatar` shown on `fit_body` against the drape `truth` on its
  // real body.
  absl::Status AddSkin(size_t avatar, const core::Positions& fit, const core::Positions& fit_body,
                       const core::Positions& truth, const Holdout& holdout,
                       const core::Triangles& body_triangles,
                       const core::Triangles& garment_triangles) {
    ASSIGN_OR_RETURN(
        const SkinVisibility s,
        MeasureVisibleSkin({&holdout.body, &body_triangles, &truth, &garment_triangles},
                           {&fit_body, &body_triangles, &fit, &garment_triangles}));
    AddSkin(s, s.share(), s.inside_share());
    if (avatars.size() <= avatar) avatars.resize(avatar + 1);
    AddPixels(s, avatars[avatar].skin);
    return absl::OkStatus();
  }

  void AddSkin(const SkinVisibility& s, double share_max, double inside_max) {
    AddPixels(s, skin);
    skin_share_max = std::max(skin_share_max, share_max);
    inside_share_max = std::max(inside_share_max, inside_max);
  }

  static void AddPixels(const SkinVisibility& from, SkinVisibility& to) {
    to.cloth_pixels += from.cloth_pixels;
    to.skin_pixels += from.skin_pixels;
    to.edge_skin_pixels += from.edge_skin_pixels;
  }

  // Another row's per-avatar errors and skin (the same avatars, another garment) added to these.
  void AddAvatars(const RowStats& other) {
    if (avatars.size() < other.avatars.size()) avatars.resize(other.avatars.size());
    for (size_t a = 0; a < other.avatars.size(); ++a) {
      avatars[a].sum_mm += other.avatars[a].sum_mm;
      avatars[a].vertices += other.avatars[a].vertices;
      AddPixels(other.avatars[a].skin, avatars[a].skin);
    }
  }

  // Each avatar's own mean error, in the avatars' order.
  std::vector<double> AvatarMeans() const {
    std::vector<double> means;
    for (const AvatarErrors& a : avatars) {
      if (a.vertices > 0) means.push_back(a.sum_mm / static_cast<double>(a.vertices));
    }
    return means;
  }

  // The sample standard deviation of `means` over the square root of their count (0 for fewer
  // than two).
  static double StandardError(const std::vector<double>& means) {
    if (means.size() < 2) return 0;
    const double k = static_cast<double>(means.size());
    double mean = 0;
    for (double m : means) mean += m / k;
    double squares = 0;
    for (double m : means) squares += (m - mean) * (m - mean);
    return std::sqrt(squares / (k - 1) / k);
  }

  v1::MethodAccuracy Finish(double drape_seconds) const {
    v1::MethodAccuracy row;
    row.set_method(method);
    row.set_cleanup(cleanup);
    std::vector<float> sorted = errors_mm;
    std::sort(sorted.begin(), sorted.end());
    double sum = 0;
    for (float e : sorted) sum += e;
    const double n = static_cast<double>(std::max<size_t>(sorted.size(), 1));
    row.set_error_mean_mm(sum / n);
    const std::vector<double> avatar_means = AvatarMeans();
    row.set_error_mean_stderr_mm(StandardError(avatar_means));
    for (const double m : avatar_means) row.add_avatar_error_mean_mm(m);
    for (const AvatarErrors& a : avatars) {
      if (a.skin.cloth_pixels == 0) continue;
      row.add_avatar_visible_skin(a.skin.share());
      row.add_avatar_visible_skin_inside(a.skin.inside_share());
    }
    if (!sorted.empty()) {
      row.set_error_p95_mm(sorted[std::min(
          sorted.size() - 1, static_cast<size_t>(0.95 * static_cast<double>(sorted.size())))]);
      row.set_error_max_mm(sorted.back());
    }
    row.set_penetration_below_0mm(static_cast<double>(below_0mm) / n);
    row.set_penetration_below_1mm(static_cast<double>(below_1mm) / n);
    const double micros = fit_micros_count ? fit_micros_sum / fit_micros_count : 0;
    row.set_fit_microseconds(micros);
    row.set_speedup(micros > 0 ? drape_seconds * 1e6 / micros : 0);
    row.set_visible_skin(skin.share());
    row.set_visible_skin_max(skin_share_max);
    row.set_visible_skin_inside(skin.inside_share());
    row.set_visible_skin_inside_max(inside_share_max);
    row.set_edge_retreat_mean_mm(
        edge_vertex_count ? edge_retreat_sum_mm / static_cast<double>(edge_vertex_count) : 0);
    return row;
  }
};

// Mean wall time of `call` in microseconds: repeated until 20 ms have passed, so a fit of a
// few microseconds is not lost in the clock's resolution.
template <typename Call>
double MicrosPerCall(Call&& call) {
  call();
  const auto start = std::chrono::steady_clock::now();
  int calls = 0;
  std::chrono::duration<double, std::micro> elapsed{0};
  do {
    call();
    ++calls;
    elapsed = std::chrono::steady_clock::now() - start;
  } while (elapsed.count() < 20000 && calls < 10000);
  return elapsed.count() / calls;
}

core::Positions FromFlat(const Eigen::VectorXf& flat) {
  return Eigen::Map<const Positions32>(flat.data(), flat.size() / 3, 3).cast<double>();
}

absl::Status CheckMethods(const AccuracyEvalSpec& spec) {
  for (const std::string& m : spec.methods) {
    if (m == kWeightsDrape && spec.truth_on_weights_body) {
      return absl::InvalidArgumentError(absl::StrCat(
          kWeightsDrape, " is the drape on the body of the weights, which is the ground truth "
          "itself with --truth-body weights; measure it against the own meshes"));
    }
    if (m != "nearest" && m != "geometric" && m != kWeightsDrape) {
      RETURN_IF_ERROR(clothing::ParseClothingMethod(m).status());
    }
    if (m == "kernel" && spec.sampled_drapes < 1) {
      return absl::InvalidArgumentError(
          "the kernel method learns from drapes of sampled bodies; give their number");
    }
  }
  if (spec.methods.empty()) return absl::InvalidArgumentError("no methods to evaluate");
  if (spec.fit_on_own_body && spec.truth_on_weights_body) {
    return absl::InvalidArgumentError(
        "fits to the own mesh are measured against drapes on the own mesh; not with "
        "--truth-body weights");
  }
  return absl::OkStatus();
}

bool Wants(const std::vector<std::string>& methods, absl::string_view method) {
  return std::find(methods.begin(), methods.end(), method) != methods.end();
}

absl::StatusOr<std::vector<Holdout>> MakeHoldouts(const body::BodyModel& body_model,
                                                  const LoadedAvatarBasis& basis,
                                                  const core::Triangles& triangles,
                                                  const AccuracyEvalSpec& spec,
                                                  body::PopulationPreset preset,
                                                  double* error_mean_mm) {
  std::vector<Holdout> holdouts;
  double error_sum = 0;
  ASSIGN_OR_RETURN(const body::PopulationSampler sampler,
                   body::PopulationSampler::Create(body_model));
  for (int i = 0; i < spec.holdout_count; ++i) {
    ASSIGN_OR_RETURN(const body::BodyParams params,
                     sampler.Sample(preset, spec.holdout_seed, static_cast<uint64_t>(i)));
    ASSIGN_OR_RETURN(core::Mesh body, body_model.BuildBody(params));
    ASSIGN_OR_RETURN(v1::AvatarWeights weights, ProjectAvatar(basis, body));
    error_sum += weights.mean_error_mm();
    const Eigen::VectorXf w =
        Eigen::Map<const Eigen::VectorXd>(weights.weights().data(), weights.weights_size())
            .cast<float>();
    const core::Positions weights_body = BodyOfWeights(basis, w.cast<double>());
    if (spec.truth_on_weights_body) body.positions = weights_body;
    ASSIGN_OR_RETURN(core::TriangleBvh surface,
                     core::TriangleBvh::Build(body.positions, triangles));
    holdouts.push_back({body.positions, std::move(surface), w, weights_body,
                        core::InterleavedFloats(body.positions)});
  }
  *error_mean_mm = spec.holdout_count ? error_sum / spec.holdout_count : 0;
  return holdouts;
}

// The rows of one garment, in table order: each model without and with clean-up, then the
// baselines.
std::vector<RowStats> EmptyRows(const std::vector<std::string>& methods) {
  std::vector<RowStats> rows;
  for (const char* m : {"paper", "linear", "quadratic", "kernel"}) {
    if (!Wants(methods, m)) continue;
    for (bool cleanup : {false, true}) {
      rows.emplace_back();
      rows.back().method = m;
      rows.back().cleanup = cleanup;
    }
  }
  for (const char* m : {"nearest", "geometric", kWeightsDrape}) {
    if (!Wants(methods, m)) continue;
    rows.emplace_back();
    rows.back().method = m;
  }
  return rows;
}

struct GarmentDrapes {
  ClothingBuildSpec spec;
  ClothingPlan plan;
  std::vector<workers::DrapeTask> truth;
  std::vector<workers::DrapeTask> on_weights_bodies;  // For kWeightsDrape; else empty.
};

// Fits every held-out avatar with every method of one garment and fills its rows.
absl::Status EvaluateGarment(const AccuracyEvalSpec& spec, const GarmentDrapes& g,
                             const std::vector<v1::DrapeResult>& examples,
                             const std::vector<v1::DrapeResult>& truths,
                             const std::vector<v1::DrapeResult>& on_weights_bodies,
                             const std::vector<Holdout>& holdouts,
                             const core::Triangles& body_triangles, std::vector<RowStats>& rows,
                             v1::GarmentAccuracy& out) {
  const v1::Garment& garment = *g.spec.garment;
  const int64_t vertex_count = garment.template_mesh().vertex_count();
  ASSIGN_OR_RETURN(const core::Mesh garment_mesh, proto::MeshFromProto(garment.template_mesh()));
  const core::Triangles garment_triangles = core::Triangulate(garment_mesh.faces);
  const GarmentEdges edges = FindGarmentEdges(garment_triangles);
  // The ground truth itself: where the drape lets skin show through its cloth, a fit cannot be
  // judged there, and it learns from such drapes.
  SkinVisibility drape_skin;
  double drape_skin_max = 0;
  for (size_t h = 0; h < holdouts.size(); ++h) {
    ASSIGN_OR_RETURN(const core::Positions truth,
                     workers::DrapeResultPositions(truths[h], vertex_count));
    ASSIGN_OR_RETURN(const SkinVisibility s,
                     MeasureSkinThroughCloth({&holdouts[h].body, &body_triangles, &truth,
                                              &garment_triangles}));
    drape_skin.cloth_pixels += s.cloth_pixels;
    drape_skin.skin_pixels += s.skin_pixels;
    drape_skin_max = std::max(drape_skin_max, s.share());
  }
  out.set_drape_skin_through(drape_skin.share());
  out.set_drape_skin_through_max(drape_skin_max);
  std::optional<clothing::ClothingFitter> fitter;
  for (RowStats& row : rows) {
    if (row.method == "nearest" || row.method == "geometric" || row.method == kWeightsDrape) {
      continue;
    }
    // Rows come in pairs (without, then with clean-up) that share one clothing basis.
    if (!row.cleanup) {
      ASSIGN_OR_RETURN(clothing::ClothingMethod method, clothing::ParseClothingMethod(row.method));
      ASSIGN_OR_RETURN(v1::ClothingBasis basis,
                       AssembleClothingBasis(g.spec, g.plan, method, examples));
      if (method == clothing::ClothingMethod::kLinear) out.set_clothing_basis_id(basis.id());
      if (!spec.clothing_dir.empty()) {
        RETURN_IF_ERROR(proto::WriteMessageFile(
            spec.clothing_dir /
                absl::StrCat(garment.name(), "-", spec.size, "-", row.method, ".fbc"),
            basis));
      }
      ASSIGN_OR_RETURN(fitter, proto::ClothingFitterFromProto(basis));
    }
    clothing::FitScratch scratch;
    Eigen::VectorXf fit;
    const auto fit_one = [&](const Holdout& h) {
      return spec.fit_on_own_body
                 ? fitter->FitToBody(h.weights, h.body_xyz, row.cleanup, scratch, fit)
                 : fitter->Fit(h.weights, row.cleanup, scratch, fit);
    };
    for (size_t h = 0; h < holdouts.size(); ++h) {
      RETURN_IF_ERROR(fit_one(holdouts[h]).status());
      ASSIGN_OR_RETURN(core::Positions truth,
                       workers::DrapeResultPositions(truths[h], vertex_count));
      const core::Positions fitted = FromFlat(fit);
      row.Add(h, fitted, truth, holdouts[h].surface, edges);
      RETURN_IF_ERROR(
          row.AddSkin(h, fitted, spec.fit_on_own_body ? holdouts[h].body : holdouts[h].weights_body,
                      truth, holdouts[h], body_triangles, garment_triangles));
    }
    row.fit_micros_sum += MicrosPerCall([&] { (void)fit_one(holdouts[0]); });
    ++row.fit_micros_count;
  }
  std::vector<Eigen::VectorXf> example_weights;
  for (int e = 0; e < g.plan.design.example_count(); ++e) {
    example_weights.push_back(g.plan.design.Weights(e).cast<float>());
  }
  for (RowStats& row : rows) {
    if (row.method == "nearest") {
      auto nearest = [&](const Eigen::VectorXf& w) {
        size_t best = 0;
        for (size_t e = 1; e < example_weights.size(); ++e) {
          if ((example_weights[e] - w).squaredNorm() < (example_weights[best] - w).squaredNorm()) {
            best = e;
          }
        }
        return best;
      };
      Eigen::VectorXf fit;
      for (size_t h = 0; h < holdouts.size(); ++h) {
        const v1::DrapeResult& chosen = examples[nearest(holdouts[h].weights)];
        ASSIGN_OR_RETURN(core::Positions positions,
                         workers::DrapeResultPositions(chosen, vertex_count));
        ASSIGN_OR_RETURN(core::Positions truth,
                         workers::DrapeResultPositions(truths[h], vertex_count));
        row.Add(h, positions, truth, holdouts[h].surface, edges);
        RETURN_IF_ERROR(row.AddSkin(h, positions, holdouts[h].weights_body, truth, holdouts[h],
                                    body_triangles, garment_triangles));
      }
      row.fit_micros_sum += MicrosPerCall([&] {
        const v1::DrapeResult& chosen = examples[nearest(holdouts[0].weights)];
        fit = Eigen::Map<const Eigen::VectorXf>(chosen.positions().data(), chosen.positions_size());
      });
      ++row.fit_micros_count;
    } else if (row.method == "geometric") {
      for (size_t h = 0; h < holdouts.size(); ++h) {
        const auto start = std::chrono::steady_clock::now();
        ASSIGN_OR_RETURN(workers::GarmentFit fit,
                         workers::GeometricFit(garment, spec.size, holdouts[h].body));
        row.fit_micros_sum += std::chrono::duration<double, std::micro>(
                                  std::chrono::steady_clock::now() - start).count();
        ++row.fit_micros_count;
        ASSIGN_OR_RETURN(core::Positions truth,
                         workers::DrapeResultPositions(truths[h], vertex_count));
        row.Add(h, fit.positions, truth, holdouts[h].surface, edges);
        // The binding fits the real body, so it is shown on it.
        RETURN_IF_ERROR(row.AddSkin(h, fit.positions, holdouts[h].body, truth, holdouts[h],
                                    body_triangles, garment_triangles));
      }
    } else if (row.method == kWeightsDrape) {
      for (size_t h = 0; h < holdouts.size(); ++h) {
        ASSIGN_OR_RETURN(core::Positions positions,
                         workers::DrapeResultPositions(on_weights_bodies[h], vertex_count));
        ASSIGN_OR_RETURN(core::Positions truth,
                         workers::DrapeResultPositions(truths[h], vertex_count));
        row.Add(h, positions, truth, holdouts[h].surface, edges);
        RETURN_IF_ERROR(row.AddSkin(h, positions, holdouts[h].weights_body, truth, holdouts[h],
                                    body_triangles, garment_triangles));
        row.fit_micros_sum += 1e6 * on_weights_bodies[h].report().seconds();
        ++row.fit_micros_count;
      }
    }
  }
  return absl::OkStatus();
}

// What both evaluations start from: the avatar basis loaded, its triangles, and the preset
// the held-out avatars are drawn from (the spec's, else the basis's own).
struct EvalBasis {
  LoadedAvatarBasis basis;
  core::Triangles triangles;
  std::string preset_name;
  body::PopulationPreset preset;
};

absl::StatusOr<EvalBasis> LoadEvalBasis(const AccuracyEvalSpec& spec) {
  EvalBasis out;
  const v1::AvatarBasis& basis_message = *spec.avatar_basis;
  out.preset_name = spec.preset.empty() ? basis_message.population().preset() : spec.preset;
  if (out.preset_name.empty()) {
    return absl::InvalidArgumentError(
        "the avatar basis has no population preset; name the held-out avatars' preset");
  }
  ASSIGN_OR_RETURN(out.preset, body::ParsePopulationPreset(out.preset_name));
  out.basis = {basis_message, {}};
  ASSIGN_OR_RETURN(out.basis.pca, proto::PcaBasisFromProto(basis_message));
  ASSIGN_OR_RETURN(core::Mesh mean, proto::MeshFromProto(basis_message.mean()));
  out.triangles = core::Triangulate(mean.faces);
  return out;
}

}  // namespace

absl::StatusOr<v1::AccuracyReport> EvaluateAccuracy(const body::BodyModel& body_model,
                                                    const AccuracyEvalSpec& spec) {
  RETURN_IF_ERROR(CheckMethods(spec));
  if (spec.holdout_count < 1) return absl::InvalidArgumentError("need at least 1 held-out avatar");
  ASSIGN_OR_RETURN(EvalBasis loaded, LoadEvalBasis(spec));
  const v1::AvatarBasis& basis_message = *spec.avatar_basis;
  const LoadedAvatarBasis& basis = loaded.basis;
  const core::Triangles& triangles = loaded.triangles;
  const std::string& preset_name = loaded.preset_name;
  const body::PopulationPreset preset = loaded.preset;

  v1::AccuracyReport report;
  report.set_avatar_basis_id(basis_message.id());
  report.set_component_count(basis_message.component_count());
  report.set_size(spec.size);
  report.set_preset(preset_name);
  report.set_holdout_seed(spec.holdout_seed);
  report.set_holdout_count(static_cast<uint32_t>(spec.holdout_count));
  report.set_truth_body(spec.truth_on_weights_body ? "weights" : "own");
  report.set_fit_body(spec.fit_on_own_body ? "own" : "weights");
  report.set_example_scale(spec.example_scale);
  report.set_simulator(workers::SimulatorDescription(spec.settings, spec.schedule));
  double avatar_error = 0;
  ASSIGN_OR_RETURN(std::vector<Holdout> holdouts,
                   MakeHoldouts(body_model, basis, triangles, spec, preset, &avatar_error));
  report.set_avatar_error_mean_mm(avatar_error);

  std::vector<GarmentDrapes> garments;
  std::vector<const workers::DrapeTask*> tasks;
  for (const v1::Garment* garment : spec.garments) {
    GarmentDrapes g;
    g.spec = {.avatar_basis = &basis_message,
              .garment = garment,
              .size = spec.size,
              .example_scale = spec.example_scale,
              .sampled_drapes = Wants(spec.methods, "kernel") ? spec.sampled_drapes : 0,
              .sample_seed = spec.sample_seed,
              .settings = spec.settings,
              .schedule = spec.schedule,
              .model_threads = spec.run.jobs};
    ASSIGN_OR_RETURN(g.plan, PlanClothingBasis(g.spec));
    for (const Holdout& h : holdouts) {
      g.truth.push_back(workers::MakeDrapeTask(*garment, spec.size, h.body, spec.settings,
                                               spec.schedule));
      if (Wants(spec.methods, kWeightsDrape)) {
        g.on_weights_bodies.push_back(workers::MakeDrapeTask(*garment, spec.size, h.weights_body,
                                                             spec.settings, spec.schedule));
      }
    }
    garments.push_back(std::move(g));
  }
  for (const GarmentDrapes& g : garments) {
    for (const workers::DrapeTask& t : g.plan.tasks) tasks.push_back(&t);
    for (const workers::DrapeTask& t : g.truth) tasks.push_back(&t);
    for (const workers::DrapeTask& t : g.on_weights_bodies) tasks.push_back(&t);
  }
  ASSIGN_OR_RETURN(std::vector<v1::DrapeResult> results, RunDrapeTasks(tasks, spec.run));

  std::vector<RowStats> overall = EmptyRows(spec.methods);
  double overall_drape_seconds = 0;
  size_t offset = 0;
  for (const GarmentDrapes& g : garments) {
    const auto begin = results.begin() + static_cast<std::ptrdiff_t>(offset);
    const std::vector<v1::DrapeResult> examples(
        begin, begin + static_cast<std::ptrdiff_t>(g.plan.tasks.size()));
    const auto truth_begin = begin + static_cast<std::ptrdiff_t>(g.plan.tasks.size());
    const auto weights_begin = truth_begin + static_cast<std::ptrdiff_t>(g.truth.size());
    const std::vector<v1::DrapeResult> truths(truth_begin, weights_begin);
    const std::vector<v1::DrapeResult> on_weights_bodies(
        weights_begin, weights_begin + static_cast<std::ptrdiff_t>(g.on_weights_bodies.size()));
    offset += g.plan.tasks.size() + g.truth.size() + g.on_weights_bodies.size();

    v1::GarmentAccuracy* out = report.add_garments();
    out->set_garment_id(g.spec.garment->id());
    out->set_garment_name(g.spec.garment->name());
    out->set_vertex_count(g.spec.garment->template_mesh().vertex_count());
    double seconds = 0;
    uint32_t overstretched = 0;
    for (const v1::DrapeResult& t : truths) {
      seconds += t.report().seconds();
      overstretched += t.report().overstretched();
    }
    seconds /= static_cast<double>(truths.size());
    out->set_drape_seconds_mean(seconds);
    double build_seconds = 0;
    for (const v1::DrapeResult& e : examples) build_seconds += e.report().seconds();
    out->set_build_drapes(static_cast<uint32_t>(examples.size()));
    out->set_build_drape_seconds(build_seconds);
    out->set_overstretched_drapes(overstretched);
    overall_drape_seconds += seconds / static_cast<double>(garments.size());

    std::vector<RowStats> rows = EmptyRows(spec.methods);
    RETURN_IF_ERROR(
        EvaluateGarment(spec, g, examples, truths, on_weights_bodies, holdouts, triangles, rows,
                        *out));
    for (size_t r = 0; r < rows.size(); ++r) {
      *out->add_methods() = rows[r].Finish(seconds);
      overall[r].errors_mm.insert(overall[r].errors_mm.end(), rows[r].errors_mm.begin(),
                                  rows[r].errors_mm.end());
      overall[r].AddAvatars(rows[r]);
      overall[r].below_0mm += rows[r].below_0mm;
      overall[r].below_1mm += rows[r].below_1mm;
      overall[r].edge_retreat_sum_mm += rows[r].edge_retreat_sum_mm;
      overall[r].edge_vertex_count += rows[r].edge_vertex_count;
      overall[r].fit_micros_sum += rows[r].fit_micros_sum / rows[r].fit_micros_count;
      ++overall[r].fit_micros_count;
      overall[r].AddSkin(rows[r].skin, rows[r].skin_share_max, rows[r].inside_share_max);
    }
  }
  for (const RowStats& row : overall) *report.add_overall() = row.Finish(overall_drape_seconds);
  return report;
}

absl::StatusOr<std::vector<AdviceAgreement>> EvaluateAdviceAgreement(
    const body::BodyModel& body_model, const AccuracyEvalSpec& spec,
    const std::vector<std::string>& sizes) {
  if (spec.holdout_count < 1) return absl::InvalidArgumentError("need at least 1 held-out avatar");
  if (sizes.size() < 2) return absl::InvalidArgumentError("advice needs at least 2 sizes");
  ASSIGN_OR_RETURN(EvalBasis loaded, LoadEvalBasis(spec));
  const v1::AvatarBasis& basis_message = *spec.avatar_basis;
  const LoadedAvatarBasis& basis = loaded.basis;
  const core::Triangles& triangles = loaded.triangles;
  const body::PopulationPreset preset = loaded.preset;
  double avatar_error = 0;
  ASSIGN_OR_RETURN(std::vector<Holdout> holdouts,
                   MakeHoldouts(body_model, basis, triangles, spec, preset, &avatar_error));

  // Per garment and size: the example drapes, then one drape per held-out body.
  std::vector<GarmentDrapes> plans;
  std::vector<const workers::DrapeTask*> tasks;
  for (const v1::Garment* garment : spec.garments) {
    for (const std::string& size : sizes) {
      GarmentDrapes g;
      g.spec = {.avatar_basis = &basis_message, .garment = garment, .size = size,
                .example_scale = spec.example_scale, .settings = spec.settings,
                .schedule = spec.schedule};
      ASSIGN_OR_RETURN(g.plan, PlanClothingBasis(g.spec));
      for (const Holdout& h : holdouts) {
        g.truth.push_back(
            workers::MakeDrapeTask(*garment, size, h.body, spec.settings, spec.schedule));
      }
      plans.push_back(std::move(g));
    }
  }
  for (const GarmentDrapes& g : plans) {
    for (const workers::DrapeTask& t : g.plan.tasks) tasks.push_back(&t);
    for (const workers::DrapeTask& t : g.truth) tasks.push_back(&t);
  }
  ASSIGN_OR_RETURN(std::vector<v1::DrapeResult> results, RunDrapeTasks(tasks, spec.run));

  // The bodies as judged: each held-out body itself, and the body of its weights.
  std::vector<AdviceBody> real_bodies;
  std::vector<AdviceBody> weight_bodies;
  for (const Holdout& h : holdouts) {
    ASSIGN_OR_RETURN(AdviceBody real, MeasureAdviceBody(h.body, triangles));
    real_bodies.push_back(std::move(real));
    ASSIGN_OR_RETURN(AdviceBody of_weights, MeasureAdviceBody(h.weights_body, triangles));
    weight_bodies.push_back(std::move(of_weights));
  }

  std::vector<AdviceAgreement> rows;
  size_t offset = 0;
  size_t plan = 0;
  for (const v1::Garment* garment : spec.garments) {
    ASSIGN_OR_RETURN(AdviceGarment advice, PrepareAdviceGarment(*garment));
    const int64_t vertex_count = garment->template_mesh().vertex_count();
    std::vector<int> indices;
    for (const std::string& size : sizes) {
      const auto it = std::find(advice.size_names.begin(), advice.size_names.end(), size);
      if (it == advice.size_names.end()) {
        return absl::InvalidArgumentError(
            absl::StrCat("garment ", garment->name(), " has no size ", size));
      }
      indices.push_back(static_cast<int>(it - advice.size_names.begin()));
    }
    // truth[s][h] and the fitter of each size.
    std::vector<std::vector<v1::DrapeResult>> truth(sizes.size());
    std::vector<clothing::ClothingFitter> fitters;
    for (size_t s = 0; s < sizes.size(); ++s, ++plan) {
      const GarmentDrapes& g = plans[plan];
      const auto begin = results.begin() + static_cast<std::ptrdiff_t>(offset);
      const std::vector<v1::DrapeResult> examples(
          begin, begin + static_cast<std::ptrdiff_t>(g.plan.tasks.size()));
      truth[s].assign(begin + static_cast<std::ptrdiff_t>(g.plan.tasks.size()),
                      begin + static_cast<std::ptrdiff_t>(g.plan.tasks.size() + g.truth.size()));
      offset += g.plan.tasks.size() + g.truth.size();
      ASSIGN_OR_RETURN(v1::ClothingBasis clothing,
                       AssembleClothingBasis(g.spec, g.plan, clothing::ClothingMethod::kLinear,
                                             examples));
      ASSIGN_OR_RETURN(clothing::ClothingFitter fitter, proto::ClothingFitterFromProto(clothing));
      fitters.push_back(std::move(fitter));
    }

    AdviceAgreement row;
    row.garment_name = garment->name();
    std::map<std::string, std::pair<double, int>> gaps;
    clothing::FitScratch scratch;
    Eigen::VectorXf fit;
    for (size_t h = 0; h < holdouts.size(); ++h) {
      std::vector<SizeJudgement> from_drape;
      std::vector<SizeJudgement> from_fit;
      for (size_t s = 0; s < sizes.size(); ++s) {
        ASSIGN_OR_RETURN(core::Positions draped,
                         workers::DrapeResultPositions(truth[s][h], vertex_count));
        ASSIGN_OR_RETURN(SizeJudgement d,
                         JudgeSize(advice, indices[s], real_bodies[h], draped));
        RETURN_IF_ERROR(fitters[s].Fit(holdouts[h].weights, /*cleanup=*/true, scratch, fit)
                            .status());
        ASSIGN_OR_RETURN(SizeJudgement f,
                         JudgeSize(advice, indices[s], weight_bodies[h], FromFlat(fit)));
        for (const clothing::RegionFitValue& dv : d.regions) {
          for (const clothing::RegionFitValue& fv : f.regions) {
            if (fv.region != dv.region) continue;
            auto& [sum, count] = gaps[std::string(clothing::FitRegionName(dv.region))];
            sum += std::abs(fv.ease_cm - dv.ease_cm);
            ++count;
          }
        }
        from_drape.push_back(std::move(d));
        from_fit.push_back(std::move(f));
      }
      const v1::SizeAdvice drape_advice = AssembleAdvice(advice, indices, from_drape, false);
      const v1::SizeAdvice fit_advice = AssembleAdvice(advice, indices, from_fit, false);
      auto position = [&](const std::string& name) {
        return std::find(sizes.begin(), sizes.end(), name) - sizes.begin();
      };
      ++row.bodies;
      ++row.drape_recommends[drape_advice.recommended_size()];
      const auto apart = std::abs(position(drape_advice.recommended_size()) -
                                  position(fit_advice.recommended_size()));
      row.same_size += apart == 0;
      row.within_one += apart <= 1;
    }
    for (const auto& [region, sum_count] : gaps) {
      row.ease_gap_cm[region] = sum_count.first / sum_count.second;
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

std::string AdviceAgreementMarkdown(const std::vector<AdviceAgreement>& rows,
                                    const std::vector<std::string>& sizes,
                                    const AccuracyEvalSpec& spec) {
  std::string md = absl::StrFormat(
      "# Size advice: fast fit against drape\n\nSizes %s judged together, %d held-out `%s` "
      "avatars (seed %d). The drape's advice judges each size draped on the body itself; the "
      "fast fit's judges the linear fit with clean-up on the body of the weights, as the fit "
      "service does. Ease gap: mean |fit - drape| of a region's ease, cm.\n\n"
      "| garment | bodies | same size | within one size | drape recommends | ease gap bust | "
      "waist | hip | thigh | upper arm | length | sleeve |\n"
      "|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|\n",
      absl::StrJoin(sizes, ","), spec.holdout_count,
      spec.preset.empty() ? spec.avatar_basis->population().preset() : spec.preset,
      spec.holdout_seed);
  int bodies = 0;
  int same = 0;
  for (const AdviceAgreement& row : rows) {
    std::vector<std::string> counts;
    for (const std::string& size : sizes) {
      const auto it = row.drape_recommends.find(size);
      counts.push_back(absl::StrCat(size, " ", it == row.drape_recommends.end() ? 0 : it->second));
    }
    auto gap = [&](const char* region) {
      const auto it = row.ease_gap_cm.find(region);
      return it == row.ease_gap_cm.end() ? std::string("-")
                                         : absl::StrFormat("%.1f", it->second);
    };
    absl::StrAppend(&md, absl::StrFormat(
                             "| %s | %d | %.0f%% | %.0f%% | %s | %s | %s | %s | %s | %s | %s | "
                             "%s |\n",
                             row.garment_name, row.bodies, 100.0 * row.same_size / row.bodies,
                             100.0 * row.within_one / row.bodies, absl::StrJoin(counts, ", "),
                             gap("bust"), gap("waist"), gap("hip"), gap("thigh"),
                             gap("upper_arm"), gap("garment_length"), gap("sleeve_length")));
    bodies += row.bodies;
    same += row.same_size;
  }
  absl::StrAppend(&md, absl::StrFormat("\nAll garments: the same size on %d of %d bodies "
                                       "(%.0f%%).\n",
                                       same, bodies, bodies ? 100.0 * same / bodies : 0.0));
  return md;
}

namespace {

void AppendTable(const google::protobuf::RepeatedPtrField<v1::MethodAccuracy>& rows,
                 std::string& md) {
  absl::StrAppend(&md,
                  "| method | clean-up | mean mm | ± mm | p95 mm | max mm | pen. < 0 mm | "
                  "pen. < 1 mm | visible skin (max) | of it inside the cloth (max) | "
                  "edge retreat mm | fit us | speed-up |\n"
                  "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const v1::MethodAccuracy& r : rows) {
    absl::StrAppend(&md, absl::StrFormat("| %s | %s | %.2f | %.2f | %.2f | %.1f | %.3f%% | "
                                         "%.3f%% | %.2f%% (%.2f%%) | %.2f%% (%.2f%%) | %+.2f | "
                                         "%.1f | %.0fx |\n",
                                         r.method(), r.cleanup() ? "yes" : "no",
                                         r.error_mean_mm(), r.error_mean_stderr_mm(),
                                         r.error_p95_mm(), r.error_max_mm(),
                                         100 * r.penetration_below_0mm(),
                                         100 * r.penetration_below_1mm(),
                                         100 * r.visible_skin(), 100 * r.visible_skin_max(),
                                         100 * r.visible_skin_inside(),
                                         100 * r.visible_skin_inside_max(),
                                         r.edge_retreat_mean_mm(), r.fit_microseconds(),
                                         r.speedup()));
  }
}

}  // namespace

std::string AccuracyReportMarkdown(const v1::AccuracyReport& report) {
  std::string md = absl::StrFormat(
      "# Fast fit against the physics drape\n\nAvatar basis `%s` (%d components), size %s, "
      "%d held-out `%s` avatars (seed %d, projection error %.2f mm mean), examples at "
      "mean +- %.2g sigma.\nErrors are per-vertex distances to the drape of the same body; "
      "penetration is measured against %s. Visible skin: pixels of the front "
      "and side views (600 px high) where the drape shows cloth and the fit shows skin, over the "
      "drape's cloth pixels (all avatars; max: the worst avatar). Of it inside the cloth: the "
      "skin pixels more than 1 cm from the drape garment's edges (hems, cuffs, necklines, "
      "waistbands), where a line of skin means the edge is in another place. Edge retreat: how "
      "far the fit's garment edges lie back into the cloth from the drape's, on average (signed; "
      "+: a hem higher, a neckline lower), where a line of skin shows along them.\n",
      report.avatar_basis_id().substr(0, 12), report.component_count(), report.size(),
      report.holdout_count(), report.preset(), report.holdout_seed(),
      report.avatar_error_mean_mm(), report.example_scale(),
      report.truth_body() == "weights"
          ? "the body the drapes are on: each held-out avatar's body of the weights (mean + "
            "Phi w, what the fit is made for), not its own mesh, so the projection's part of the "
            "error is left out"
          : "the real held-out body");
  absl::StrAppend(&md, report.fit_body() == "own"
                           ? "The fits are made for each held-out avatar's own mesh and shown on "
                             "it: the model's garment for the body of the weights follows the "
                             "mesh along the body's normals, and the clean-up clears the mesh.\n"
                           : "The fits are made for each held-out avatar's body of the weights "
                             "and shown on it.\n");
  const bool floor =
      std::any_of(report.overall().begin(), report.overall().end(),
                  [](const v1::MethodAccuracy& r) { return r.method() == kWeightsDrape; });
  if (floor) {
    absl::StrAppend(&md, absl::StrFormat(
                             "%s: the drape on each held-out avatar's body of the weights, shown "
                             "on that body like a fit (its fit us: the drape's time). A fit "
                             "takes only the weights, so even a perfect one misses by this much: "
                             "the projection's part of every fit's error.\n",
                             kWeightsDrape));
  }
  for (const v1::GarmentAccuracy& g : report.garments()) {
    absl::StrAppend(
        &md, absl::StrFormat("\n## %s (%d vertices)\n\nDrape: %.2f s mean; %d of %d held-out "
                             "drapes flagged overstretched; skin through the drapes' own cloth "
                             "%.2f%% (worst %.2f%%).\nBuild: %d drapes (axis examples and "
                             "sampled bodies), %.1f min on one core, about %.1f min on two "
                             "workers.\n\n",
                             g.garment_name(), g.vertex_count(), g.drape_seconds_mean(),
                             g.overstretched_drapes(), report.holdout_count(),
                             100 * g.drape_skin_through(), 100 * g.drape_skin_through_max(),
                             g.build_drapes(), g.build_drape_seconds() / 60,
                             g.build_drape_seconds() / 120));
    AppendTable(g.methods(), md);
  }
  absl::StrAppend(&md, absl::StrFormat("\n## All %d garments\n\n", report.garments_size()));
  AppendTable(report.overall(), md);
  return md;
}

}  // namespace fitbase::pipeline
