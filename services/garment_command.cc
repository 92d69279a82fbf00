// fitbase garment import: a catalogue garment, fitted to a basis's mean avatar.
#include <iostream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "core/status_macros.h"
#include "proto/message_file.h"
#include "services/cli_context.h"
#include "services/garment_importer.h"

namespace fitbase::services {
namespace {

struct GarmentFlags {
  std::string mhclo;
  std::string obj;
  std::string basis;
  std::string name;
  std::string sizes = "S,M,L,XL";
  std::vector<std::string> size_meshes;
  std::string out;
};

absl::Status RunImport(const CliContext& context, const GarmentFlags& flags) {
  GarmentImportRequest request;
  request.mhclo = flags.mhclo;
  request.obj = flags.obj;
  request.name = flags.name;
  request.sizes = absl::StrSplit(flags.sizes, ',', absl::SkipWhitespace());
  for (const std::string& entry : flags.size_meshes) {
    const std::vector<std::string> parts = absl::StrSplit(entry, absl::MaxSplits('=', 1));
    if (parts.size() != 2 || parts[0].empty() || parts[1].empty()) {
      return absl::InvalidArgumentError(
          absl::StrCat("--size-mesh '", entry, "' is not SIZE=PATH"));
    }
    request.size_meshes[parts[0]] = parts[1];
  }
  v1::AvatarBasis basis;
  RETURN_IF_ERROR(proto::ReadMessageFile(flags.basis, &basis));
  ASSIGN_OR_RETURN(core::BodyModel model, core::BodyModel::Load(ResolveDataDir(context)));
  ASSIGN_OR_RETURN(v1::Garment garment, ImportGarment(model, basis, request));
  RETURN_IF_ERROR(proto::WriteMessageFile(flags.out, garment));
  std::cout << "garment " << garment.name() << " (" << garment.id().substr(0, 12) << "): "
            << garment.template_mesh().vertex_count() << " vertices, sizes " << flags.sizes
            << ", on basis " << basis.id().substr(0, 12) << "\nwrote " << flags.out << "\n";
  return absl::OkStatus();
}

}  // namespace

void AddGarmentCommands(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<GarmentFlags>();
  CLI::App* garment = app.add_subcommand("garment", "Catalogue garments");
  garment->require_subcommand(1);
  CLI::App* import = garment->add_subcommand(
      "import", "Import a garment and fit its template to a basis's mean avatar");
  auto* mhclo = import->add_option("--mhclo", flags->mhclo, "MakeHuman garment binding (.mhclo)");
  auto* obj = import->add_option("--obj", flags->obj,
                                 "OBJ already placed on the basis's mean avatar (meters)");
  mhclo->excludes(obj);
  import->add_option("--basis", flags->basis, "Avatar basis (.fbb)")->required();
  import->add_option("--name", flags->name, "Garment name (default: the file's stem)");
  import->add_option("--sizes", flags->sizes,
                     "Comma-separated sizes; M is the template (default: S,M,L,XL)");
  import->add_option("--size-mesh", flags->size_meshes,
                     "SIZE=PATH: a retailer's own rest mesh for that size (repeatable)");
  import->add_option("--out", flags->out, "Output garment (.fbg)")->required();
  import->callback([&context, flags] {
    context.action = [&context, flags] { return RunImport(context, *flags); };
  });
}

}  // namespace fitbase::services
