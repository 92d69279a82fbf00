// fitbase eval: the accuracy table of the fast fit against the physics drape, or (--advice)
// the agreement of its size advice with the drape's.
#include <iostream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "cli/cli_context.h"
#include "core/file_util.h"
#include "core/status_macros.h"
#include "pipeline/accuracy_eval.h"
#include "pipeline/clothing_basis_builder.h"
#include "proto/json_codec.h"
#include "proto/message_file.h"

namespace fitbase::cli {
namespace {

namespace fs = std::filesystem;

struct EvalFlags {
  std::string basis;
  std::vector<std::string> garments;
  std::string size = "M";
  int holdout = 20;
  uint64_t seed = 2;
  std::string preset;
  std::string truth_body = "own";
  std::string fit_body = "weights";
  std::string methods = "paper,linear,quadratic,nearest,geometric";
  double scale = 1.0;
  int samples = 0;
  uint64_t sample_seed = 1;
  int jobs = 2;
  ClothFlags cloth;
  workers::DrapeSchedule schedule;
  std::string cache;
  std::string out;
  std::string advice_sizes;
};

absl::Status RunEval(const CliContext& context, const EvalFlags& flags) {
  ASSIGN_OR_RETURN(const workers::ClothSettings settings, ClothSettingsFromFlags(flags.cloth));
  v1::AvatarBasis basis;
  RETURN_IF_ERROR(proto::ReadMessageFile(flags.basis, &basis));
  std::vector<v1::Garment> garments(flags.garments.size());
  for (size_t i = 0; i < garments.size(); ++i) {
    RETURN_IF_ERROR(proto::ReadMessageFile(flags.garments[i], &garments[i]));
  }
  ASSIGN_OR_RETURN(body::BodyModel model, body::BodyModel::Load(ResolveDataDir(context)));
  const std::filesystem::path out = flags.out;
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) {
    return absl::InvalidArgumentError(
        absl::StrCat("cannot create --out ", out.string(), ": ", ec.message()));
  }
  pipeline::AccuracyEvalSpec spec;
  spec.avatar_basis = &basis;
  for (const v1::Garment& g : garments) spec.garments.push_back(&g);
  spec.size = flags.size;
  spec.holdout_count = flags.holdout;
  spec.holdout_seed = flags.seed;
  spec.preset = flags.preset;
  spec.truth_on_weights_body = flags.truth_body == "weights";
  spec.fit_on_own_body = flags.fit_body == "own";
  spec.methods = absl::StrSplit(flags.methods, ',', absl::SkipWhitespace());
  spec.example_scale = flags.scale;
  spec.sampled_drapes = flags.samples;
  spec.sample_seed = flags.sample_seed;
  spec.settings = settings;
  spec.schedule = flags.schedule;
  spec.run = {.cache_dir = flags.cache.empty() ? out / "drapes" : fs::path(flags.cache),
              .jobs = flags.jobs,
              .label = "drapes"};
  spec.clothing_dir = out;
  if (!flags.advice_sizes.empty()) {
    const std::vector<std::string> sizes =
        absl::StrSplit(flags.advice_sizes, ',', absl::SkipWhitespace());
    ASSIGN_OR_RETURN(std::vector<pipeline::AdviceAgreement> rows,
                     pipeline::EvaluateAdviceAgreement(model, spec, sizes));
    const std::string markdown = pipeline::AdviceAgreementMarkdown(rows, sizes, spec);
    RETURN_IF_ERROR(core::WriteFileAtomically(out / "advice.md", markdown));
    std::cout << markdown << "\nwrote " << (out / "advice.md").string() << "\n";
    return absl::OkStatus();
  }
  ASSIGN_OR_RETURN(v1::AccuracyReport report, pipeline::EvaluateAccuracy(model, spec));
  const std::string markdown = pipeline::AccuracyReportMarkdown(report);
  RETURN_IF_ERROR(core::WriteFileAtomically(out / "report.md", markdown));
  RETURN_IF_ERROR(core::WriteFileAtomically(out / "report.json", proto::ToJson(report) + "\n"));
  std::cout << markdown << "\nwrote " << (out / "report.md").string() << " and "
            << (out / "report.json").string() << "\n";
  return absl::OkStatus();
}

}  // namespace

void AddEvalCommand(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<EvalFlags>();
  CLI::App* eval = app.add_subcommand(
      "eval", "Accuracy of the fast fit against the physics drape on held-out avatars");
  eval->add_option("--basis", flags->basis, "Avatar basis (.fbb)")->required();
  eval->add_option("--garment", flags->garments, "Garments imported on that basis (.fbg)")
      ->required()
      ->delimiter(',');
  eval->add_option("--size", flags->size, "Size name (default: M)");
  eval->add_option("--advice", flags->advice_sizes,
                   "Instead of the accuracy table: the size advice of the fast fit against the "
                   "drape's, over these sizes judged together (e.g. S,M,L,XL); writes advice.md");
  eval->add_option("--holdout", flags->holdout, "Held-out avatars (default: 20)")
      ->check(CLI::Range(1, 100000));
  eval->add_option("--seed", flags->seed,
                   "Seed of the held-out avatars; use another than the basis's (default: 2)");
  eval->add_option("--preset", flags->preset,
                   "Population of the held-out avatars (default: the basis's)");
  eval->add_option("--truth-body", flags->truth_body,
                   "What the ground-truth drapes are on: own (each held-out avatar's mesh) or "
                   "weights (its body of the weights, which the fit is made for: the error "
                   "without the projection's part) (default: own)")
      ->check(CLI::IsMember({"own", "weights"}));
  eval->add_option("--fit-body", flags->fit_body,
                   "What the fits are made for and shown on: weights (each held-out avatar's "
                   "body of the weights, as the fit service does when given only weights) or "
                   "own (its own mesh, as the service does when given the mesh too; not with "
                   "--truth-body weights) (default: weights)")
      ->check(CLI::IsMember({"own", "weights"}));
  eval->add_option("--methods", flags->methods,
                   "Comma-separated: paper, linear, quadratic, kernel, nearest, geometric, "
                   "weights-drape (each held-out body's drape on its body of the weights: what "
                   "no fit from the weights can do better than) (default: all but kernel and "
                   "weights-drape)");
  eval->add_option("--samples", flags->samples,
                   "Bodies sampled from the basis's population and draped per garment, to train "
                   "the kernel method (default: 0)")
      ->check(CLI::Range(0, pipeline::kMaxSampledDrapes));
  eval->add_option("--sample-seed", flags->sample_seed,
                   "Seed of the sampled bodies (default: 1)");
  eval->add_option("--scale", flags->scale,
                   "Examples at mean +- scale x sigma_k (default: 1)")
      ->check(CLI::PositiveNumber);
  eval->add_option("--jobs", flags->jobs,
                   "Drapes side by side, and threads of the kernel model's search (default: 2)")
      ->check(CLI::Range(1, 256));
  AddClothOptions(eval, flags->cloth);
  AddDrapeScheduleOptions(eval, flags->schedule);
  eval->add_option("--cache", flags->cache,
                   "Folder of drape results reused by content key (default: OUT/drapes)");
  eval->add_option("--out", flags->out,
                   "Folder for report.md, report.json, the clothing bases and the drape cache")
      ->required();
  eval->callback([&context, flags] {
    context.action = [&context, flags] { return RunEval(context, *flags); };
  });
}

}  // namespace fitbase::cli
