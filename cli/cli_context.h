#ifndef FITBASE_CLI_CLI_CONTEXT_H_
#define FITBASE_CLI_CLI_CONTEXT_H_

#include <filesystem>
#include <functional>
#include <string>

#include "CLI/CLI.hpp"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "workers/cloth_solver.h"
#include "workers/drape.h"

namespace fitbase::cli {

// Shared by the `fitbase` subcommands: each parses its flags into its own state and sets
// `action`, which main runs after parsing, so flag errors and run errors are reported apart.
struct CliContext {
  std::string data_dir;  // --data, resolved by ResolveDataDir().
  std::function<absl::Status()> action;
};

// --data if given, else $FITBASE_DATA, else data/makehuman beside the build folder of this
// executable, else ./data/makehuman.
std::filesystem::path ResolveDataDir(const CliContext& context);

// --homotopy-steps and --relax-steps, for every command that drapes.
void AddDrapeScheduleOptions(CLI::App* command, workers::DrapeSchedule& schedule);

// The physics drape's settings a user may change, for every command that drapes.
struct ClothFlags {
  bool no_supports = false;
  double friction = 0;
  double cuff_friction = 0;
  double skin_tie = workers::ClothSettings{}.skin_tie;
};

// --no-supports, --friction, --cuff-friction and --skin-tie.
void AddClothOptions(CLI::App* command, ClothFlags& flags);

// The physics drape's settings from those flags; InvalidArgument naming the flag for a value
// CheckFriction or CheckSkinTie refuses (CLI11's ranges let NaN through), and for both
// --friction and --skin-tie (friction replaces the ties).
absl::StatusOr<workers::ClothSettings> ClothSettingsFromFlags(const ClothFlags& flags);

void AddAvatarCommand(CLI::App& app, CliContext& context);
void AddPopulationCommand(CLI::App& app, CliContext& context);
void AddBasisCommands(CLI::App& app, CliContext& context);
void AddGarmentCommands(CLI::App& app, CliContext& context);
void AddDrapeCommand(CLI::App& app, CliContext& context);
void AddClothingCommands(CLI::App& app, CliContext& context);
void AddEvalCommand(CLI::App& app, CliContext& context);
void AddKeysCommand(CLI::App& app, CliContext& context);
void AddServeCommand(CLI::App& app, CliContext& context);
void AddBuildCommands(CLI::App& app, CliContext& context);
void AddCustomerCommands(CLI::App& app, CliContext& context);
void AddLoadtestCommand(CLI::App& app, CliContext& context);
void AddStoreCommands(CLI::App& app, CliContext& context);
void AddRenderCommand(CLI::App& app, CliContext& context);

}  // namespace fitbase::cli

#endif  // FITBASE_CLI_CLI_CONTEXT_H_
