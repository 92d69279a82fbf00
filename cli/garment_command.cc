// fitbase garment import|upload: a catalogue garment, fitted to a basis's mean avatar here or
// by the coordinator.
#include <iostream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "cli/cli_context.h"
#include "cli/remote_flags.h"
#include "core/status_macros.h"
#include "fitbase/v1/catalog.grpc.pb.h"
#include "pipeline/garment_importer.h"
#include "proto/message_file.h"
#include "services/rpc/channel.h"
#include "services/rpc/grpc_status.h"

namespace fitbase::cli {
namespace {

struct GarmentFlags {
  std::string mhclo;
  std::string obj;
  std::string basis;
  std::string name;
  std::string type;
  std::string cuffs;
  std::string sizes = "S,M,L,XL";
  std::vector<std::string> size_meshes;
  std::string out;
  RemoteFlags remote;
  std::string basis_id;
};

// The files the flags name, read, with the name and sizes the flags give.
absl::StatusOr<pipeline::GarmentImportRequest> ReadRequest(const GarmentFlags& flags) {
  pipeline::GarmentImportPaths paths;
  paths.mhclo = flags.mhclo;
  paths.obj = flags.obj;
  for (const std::string& entry : flags.size_meshes) {
    const std::vector<std::string> parts = absl::StrSplit(entry, absl::MaxSplits('=', 1));
    if (parts.size() != 2 || parts[0].empty() || parts[1].empty()) {
      return absl::InvalidArgumentError(
          absl::StrCat("--size-mesh '", entry, "' is not SIZE=PATH"));
    }
    paths.size_meshes[parts[0]] = parts[1];
  }
  ASSIGN_OR_RETURN(pipeline::GarmentImportRequest request, pipeline::ReadGarmentImportFiles(paths));
  request.name = flags.name;
  request.sizes = absl::StrSplit(flags.sizes, ',', absl::SkipWhitespace());
  request.garment_type = flags.type;
  ASSIGN_OR_RETURN(request.cuffs, pipeline::ParseCuffs(flags.cuffs));
  return request;
}

v1::SourceFile ToProto(const pipeline::SourceFile& file) {
  v1::SourceFile proto;
  proto.set_name(file.name);
  proto.set_content(file.bytes);
  return proto;
}

absl::Status RunImport(const CliContext& context, const GarmentFlags& flags) {
  ASSIGN_OR_RETURN(pipeline::GarmentImportRequest request, ReadRequest(flags));
  v1::AvatarBasis basis;
  RETURN_IF_ERROR(proto::ReadMessageFile(flags.basis, &basis));
  ASSIGN_OR_RETURN(body::BodyModel model, body::BodyModel::Load(ResolveDataDir(context)));
  ASSIGN_OR_RETURN(v1::Garment garment, pipeline::ImportGarment(model, basis, request));
  RETURN_IF_ERROR(proto::WriteMessageFile(flags.out, garment));
  std::cout << "garment " << garment.name() << " (" << garment.id().substr(0, 12) << "): "
            << garment.template_mesh().vertex_count() << " vertices, sizes " << flags.sizes
            << ", on basis " << basis.id().substr(0, 12) << "\nwrote " << flags.out << "\n";
  return absl::OkStatus();
}

absl::Status RunUpload(const GarmentFlags& flags) {
  ASSIGN_OR_RETURN(pipeline::GarmentImportRequest request, ReadRequest(flags));
  v1::UploadGarmentRequest upload;
  upload.set_avatar_basis_id(flags.basis_id);
  upload.set_name(request.name);
  *upload.mutable_obj() = ToProto(request.obj);
  if (request.mhclo.has_value()) *upload.mutable_mhclo() = ToProto(*request.mhclo);
  for (const std::string& size : request.sizes) upload.add_sizes(size);
  upload.set_garment_type(request.garment_type);
  if (pipeline::DeclaresCuffs(request.cuffs)) *upload.mutable_cuffs() = request.cuffs;
  for (const auto& [size, file] : request.size_meshes) {
    (*upload.mutable_size_meshes())[size] = ToProto(file);
  }
  auto stub = v1::Catalog::NewStub(rpc::OpenChannel(flags.remote.address));
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> call,
                   NewCallContext(flags.remote, absl::Seconds(flags.remote.timeout_seconds)));
  v1::UploadGarmentResponse response;
  RETURN_IF_ERROR(rpc::FromGrpcStatus(stub->UploadGarment(call.get(), upload, &response)));
  std::cout << "garment " << response.garment_id() << " "
            << (response.created() ? "stored" : "already stored") << ": "
            << response.vertex_count() << " vertices, sizes " << flags.sizes << "\n";
  return absl::OkStatus();
}

// The flags both commands take: the garment's files, name and sizes.
void AddSourceOptions(CLI::App* command, GarmentFlags& flags) {
  auto* mhclo = command->add_option("--mhclo", flags.mhclo, "MakeHuman garment binding (.mhclo)");
  auto* obj = command->add_option("--obj", flags.obj,
                                  "OBJ already placed on the basis's mean avatar (meters)");
  mhclo->excludes(obj);
  command->add_option("--name", flags.name, "Garment name (default: the file's stem)");
  command->add_option("--type", flags.type,
                      "For size advice: knit, fitted, shirt or jacket (default shirt; README "
                      "\"Size advice\")");
  command->add_option("--sizes", flags.sizes,
                      "Comma-separated sizes; M is the template (default: S,M,L,XL)");
  command->add_option("--cuffs", flags.cuffs,
                      "Openings that are elastic cuffs: sleeves, legs, sleeves,legs or none "
                      "(default none; docs/drape.md, \"Elastic cuffs\")");
  command->add_option("--size-mesh", flags.size_meshes,
                      "SIZE=PATH: a retailer's own rest mesh for that size (repeatable)");
}

}  // namespace

void AddGarmentCommands(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<GarmentFlags>();
  CLI::App* garment = app.add_subcommand("garment", "Catalogue garments");
  garment->require_subcommand(1);
  CLI::App* import = garment->add_subcommand(
      "import", "Import a garment and fit its template to a basis's mean avatar");
  AddSourceOptions(import, *flags);
  import->add_option("--basis", flags->basis, "Avatar basis (.fbb)")->required();
  import->add_option("--out", flags->out, "Output garment (.fbg)")->required();
  import->callback([&context, flags] {
    context.action = [&context, flags] { return RunImport(context, *flags); };
  });

  CLI::App* upload = garment->add_subcommand(
      "upload", "Upload a garment to the coordinator, which imports it for your tenant");
  AddSourceOptions(upload, *flags);
  AddRemoteOptions(upload, flags->remote);
  upload->add_option("--basis-id", flags->basis_id, "Avatar basis id (stored on the coordinator)")
      ->required();
  upload->callback([&context, flags] { context.action = [flags] { return RunUpload(*flags); }; });
}

}  // namespace fitbase::cli
