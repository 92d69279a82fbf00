// The `fitbase` command line: one binary for every offline job (and later the servers).
#include <iostream>

#include "CLI/CLI.hpp"
#include "cli/cli_context.h"

int main(int argc, char** argv) {
  CLI::App app{"fitbase: garment fit from data (Gillies, Ballin, Csaji, WSCG 2004)"};
  app.require_subcommand(1);
  fitbase::cli::CliContext context;
  app.add_option("--data", context.data_dir,
                 "MakeHuman data folder (default: $FITBASE_DATA, else data/makehuman)");
  fitbase::cli::AddAvatarCommand(app, context);
  fitbase::cli::AddPopulationCommand(app, context);
  fitbase::cli::AddBasisCommands(app, context);
  fitbase::cli::AddGarmentCommands(app, context);
  fitbase::cli::AddDrapeCommand(app, context);
  fitbase::cli::AddClothingCommands(app, context);
  fitbase::cli::AddEvalCommand(app, context);
  fitbase::cli::AddKeysCommand(app, context);
  fitbase::cli::AddServeCommand(app, context);
  fitbase::cli::AddBuildCommands(app, context);
  fitbase::cli::AddCustomerCommands(app, context);
  fitbase::cli::AddLoadtestCommand(app, context);
  fitbase::cli::AddStoreCommands(app, context);
  fitbase::cli::AddRenderCommand(app, context);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (const absl::Status status = context.action(); !status.ok()) {
    std::cerr << "fitbase: error: " << status.message() << " ["
              << absl::StatusCodeToString(status.code()) << "]\n";
    return 1;
  }
  return 0;
}
