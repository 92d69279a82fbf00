// fitbase drape: one garment, one size, one body.
#include <iostream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "cli/cli_context.h"
#include "core/file_util.h"
#include "core/garment_obj.h"
#include "core/status_macros.h"
#include "pipeline/avatar_file.h"
#include "proto/garment_codec.h"
#include "proto/json_codec.h"
#include "proto/message_file.h"
#include "workers/cloth_solver.h"
#include "workers/garment_drape.h"

namespace fitbase::cli {
namespace {

struct DrapeFlags {
  std::string garment;
  std::string size = "M";
  std::string avatar;
  std::string out;
  std::string report;
  std::string method = "drape";
  ClothFlags cloth;
  workers::DrapeSchedule schedule;
};

absl::Status RunDrape(const DrapeFlags& flags) {
  if (flags.method != "drape" && flags.method != "geometric") {
    return absl::InvalidArgumentError(
        absl::StrCat("--method is '", flags.method, "'; expected drape or geometric"));
  }
  ASSIGN_OR_RETURN(const workers::ClothSettings settings, ClothSettingsFromFlags(flags.cloth));
  if ((flags.cloth.no_supports || flags.cloth.friction > 0 || flags.cloth.cuff_friction > 0 ||
       flags.cloth.skin_tie != workers::ClothSettings{}.skin_tie) &&
      flags.method != "drape") {
    return absl::InvalidArgumentError(
        "--no-supports, --friction, --cuff-friction and --skin-tie are settings of the physics "
        "drape only");
  }
  v1::Garment garment;
  RETURN_IF_ERROR(proto::ReadMessageFile(flags.garment, &garment));
  ASSIGN_OR_RETURN(core::Mesh avatar, pipeline::ReadAvatarObj(flags.avatar));
  ASSIGN_OR_RETURN(
      workers::GarmentFit fit,
      flags.method == "drape"
          ? workers::DrapeGarment(garment, flags.size, avatar.positions, settings, flags.schedule)
          : workers::GeometricFit(garment, flags.size, avatar.positions));
  ASSIGN_OR_RETURN(core::GarmentMesh mesh, proto::GarmentTemplateFromProto(garment));
  mesh.mesh.positions = fit.positions;
  RETURN_IF_ERROR(core::WriteGarmentObj(flags.out, mesh));
  const std::string json = proto::ToJson(fit.report);
  if (!flags.report.empty()) RETURN_IF_ERROR(core::WriteFileAtomically(flags.report, json + "\n"));
  const v1::DrapeReport& r = fit.report;
  std::cout << absl::StrFormat(
      "%s %s size %s (%s): penetration <0 mm %.2f%%, <1 mm %.2f%%; strain mean %.2f%%, p99 "
      "%.2f%% (stretch %.2f%%, compression %.2f%%), max %.2f%%%s; ease mean %.1f mm; %.2f s\n"
      "wrote %s\n",
      flags.method, garment.name(), flags.size, flags.avatar, 100 * r.penetration_below_0mm(),
      100 * r.penetration_below_1mm(), 100 * r.strain_mean(), 100 * r.strain_p99(),
      100 * r.stretch_p99(), 100 * r.compression_p99(), 100 * r.strain_max(),
      r.overstretched() ? " (OVERSTRETCHED: size too small)" : "", r.ease_mean_mm(),
      r.seconds(), flags.out);
  std::string supports;
  if (r.has_waistband_above_navel_mm()) {
    absl::StrAppendFormat(&supports, " waistband %+.1f cm above the navel",
                          r.waistband_above_navel_mm() / 10);
    if (r.has_waistband_crotch_to_navel()) {
      absl::StrAppendFormat(&supports, " (%.0f%% of the way from the crotch up to it)",
                            100 * r.waistband_crotch_to_navel());
    }
    supports += ";";
  }
  if (r.has_collar_above_neck_base_mm()) {
    absl::StrAppendFormat(&supports, " collar %+.1f cm above the neck base;",
                          r.collar_above_neck_base_mm() / 10);
  }
  if (r.has_hem_above_ankle_mm()) {
    absl::StrAppendFormat(&supports, " leg hems %+.1f cm above the ankle;",
                          r.hem_above_ankle_mm() / 10);
  }
  if (r.has_cuff_gap_mm()) {
    absl::StrAppendFormat(&supports, " %u elastic cuffs %.1f mm from the skin;", r.cuff_count(),
                          r.cuff_gap_mm());
  }
  if (!supports.empty()) {
    supports.pop_back();
    std::cout << "supports:" << supports << "\n";
  }
  if (r.has_carried_girth_ratio()) {
    std::cout << absl::StrFormat(
        "ties: the size's girth carried onto this body is %.3f of its own; ties and supports "
        "%.3g times as firm\n",
        r.carried_girth_ratio(), r.tie_factor());
  }
  return absl::OkStatus();
}

}  // namespace

void AddDrapeScheduleOptions(CLI::App* command, workers::DrapeSchedule& schedule) {
  command
      ->add_option("--homotopy-steps", schedule.homotopy_steps,
                   absl::StrCat("Drape steps moving the body from the mean avatar (default: ",
                                schedule.homotopy_steps, ")"))
      ->check(CLI::Range(0, 10000));
  command
      ->add_option("--relax-steps", schedule.relax_steps,
                   absl::StrCat("Drape steps relaxing on the target body (default: ",
                                schedule.relax_steps, ")"))
      ->check(CLI::Range(0, 10000));
}

void AddClothOptions(CLI::App* command, ClothFlags& flags) {
  command->add_flag("--no-supports", flags.no_supports,
                    "Without the supports for bodies far from the mean (an elastic waistband "
                    "and collars held at their height), as drapes were before them");
  command
      ->add_option("--friction", flags.friction,
                   "Coulomb friction's mu in place of the ties to the skin (default: 0, the "
                   "ties)")
      ->check(CLI::Range(0.0, workers::kMaxFriction));
  command
      ->add_option("--cuff-friction", flags.cuff_friction,
                   "Coulomb friction's mu on the garment's declared cuffs on top of their ties "
                   "(default: 0, the ties alone)")
      ->check(CLI::Range(0.0, workers::kMaxFriction));
  command
      ->add_option(
          "--skin-tie", flags.skin_tie,
          absl::StrCat("The ties' stiffness, N/m per kg of cloth (default: ", flags.skin_tie, ")"))
      ->check(CLI::Range(0.0, workers::kMaxSkinTie));
}

absl::StatusOr<workers::ClothSettings> ClothSettingsFromFlags(const ClothFlags& flags) {
  RETURN_IF_ERROR(workers::CheckFriction(flags.friction, "--friction"));
  RETURN_IF_ERROR(workers::CheckFriction(flags.cuff_friction, "--cuff-friction"));
  RETURN_IF_ERROR(workers::CheckSkinTie(flags.skin_tie, "--skin-tie"));
  workers::ClothSettings settings;
  if (flags.friction > 0 && flags.skin_tie != settings.skin_tie) {
    return absl::InvalidArgumentError(
        "--skin-tie and --friction together: friction takes the ties' place");
  }
  if (flags.no_supports) settings = workers::WithoutSupports(settings);
  settings.friction = flags.friction;
  settings.cuff_friction = flags.cuff_friction;
  settings.skin_tie = flags.skin_tie;
  return settings;
}

void AddDrapeCommand(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<DrapeFlags>();
  CLI::App* drape = app.add_subcommand("drape", "Drape a garment size onto an avatar (physics)");
  drape->add_option("--garment", flags->garment, "Garment (.fbg)")->required();
  drape->add_option("--size", flags->size, "Size name (default: M)");
  drape->add_option("--avatar", flags->avatar, "Body avatar OBJ (meters)")->required();
  drape->add_option("--out", flags->out, "Draped garment OBJ (template's vertex order)")
      ->required();
  drape->add_option("--report", flags->report, "Fit metrics as JSON");
  AddDrapeScheduleOptions(drape, flags->schedule);
  drape->add_option("--method", flags->method,
                    "drape (physics, default) or geometric (the .mhclo binding baseline)");
  AddClothOptions(drape, flags->cloth);
  drape->callback([&context, flags] { context.action = [flags] { return RunDrape(*flags); }; });
}

}  // namespace fitbase::cli
