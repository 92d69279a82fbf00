// The `fitbase` command line: one binary for every offline job (and later the servers).
#include <iostream>

#include "CLI/CLI.hpp"
#include "services/cli_context.h"

int main(int argc, char** argv) {
  CLI::App app{"fitbase: garment fit from data (Gillies, Ballin, Csaji, WSCG 2004)"};
  app.require_subcommand(1);
  fitbase::services::CliContext context;
  app.add_option("--data", context.data_dir,
                 "MakeHuman data folder (default: $FITBASE_DATA, else data/makehuman)");
  fitbase::services::AddAvatarCommand(app, context);
  fitbase::services::AddPopulationCommand(app, context);
  fitbase::services::AddBasisCommands(app, context);
  fitbase::services::AddGarmentCommands(app, context);
  fitbase::services::AddDrapeCommand(app, context);
  fitbase::services::AddClothingCommands(app, context);
  fitbase::services::AddEvalCommand(app, context);
  fitbase::services::AddKeysCommand(app, context);
  fitbase::services::AddServeCommand(app, context);
  fitbase::services::AddBuildCommands(app, context);
  fitbase::services::AddCustomerCommands(app, context);
  fitbase::services::AddLoadtestCommand(app, context);
  fitbase::services::AddStoreCommands(app, context);
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
