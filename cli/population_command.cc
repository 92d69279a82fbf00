// fitbase population: a seeded population of avatars.
#include <iostream>

#include "absl/strings/str_cat.h"
#include "cli/cli_context.h"
#include "core/status_macros.h"
#include "pipeline/population_folder.h"

namespace fitbase::cli {
namespace {

constexpr int64_t kMaxPopulation = 100000;

struct PopulationFlags {
  std::string preset = "all";
  int64_t count = 0;
  uint64_t seed = 1;
  std::string out;
  bool calibration = false;
};

absl::Status RunPopulation(const CliContext& context, const PopulationFlags& flags) {
  ASSIGN_OR_RETURN(body::PopulationPreset preset, body::ParsePopulationPreset(flags.preset));
  if (flags.count < 1 || flags.count > kMaxPopulation) {
    return absl::InvalidArgumentError(
        absl::StrCat("--count is ", flags.count, "; expected 1 to ", kMaxPopulation));
  }
  ASSIGN_OR_RETURN(body::BodyModel model, body::BodyModel::Load(ResolveDataDir(context)));
  std::vector<body::CalibratedAvatar> calibration;
  RETURN_IF_ERROR(pipeline::WritePopulationFolder(model, preset, flags.seed, flags.count,
                                                  flags.out, &calibration));
  std::cout << "wrote " << flags.count << " avatars (preset " << flags.preset << ", seed "
            << flags.seed << ") to " << flags.out << "\n";
  if (flags.calibration && !calibration.empty()) {
    std::cout << "\n" << pipeline::CalibrationTable(calibration);
  }
  return absl::OkStatus();
}

}  // namespace

void AddPopulationCommand(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<PopulationFlags>();
  CLI::App* command =
      app.add_subcommand("population", "Sample a seeded population of adult avatars");
  command->add_option("--preset", flags->preset,
                      "women, men or all, calibrated to the ANSUR II survey (README); "
                      "women-wide, men-wide or all-wide, the first wide samplers (default: all)");
  command->add_flag("--calibration", flags->calibration,
                    "Print how the population reproduces the survey (calibrated presets)");
  command->add_option("--count", flags->count, "Number of avatars")->required();
  command->add_option("--seed", flags->seed, "Random seed (default: 1)");
  command->add_option("--out", flags->out,
                      "Output folder: population.json, params.jsonl, avatar-NNNNN.obj")
      ->required();
  command->callback([&context, flags] {
    context.action = [&context, flags] { return RunPopulation(context, *flags); };
  });
}

}  // namespace fitbase::cli
