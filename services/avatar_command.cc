// fitbase avatar: one MakeHuman body from parameters.
#include <iostream>

#include "absl/strings/str_cat.h"
#include "core/body_model.h"
#include "core/file_util.h"
#include "core/obj_io.h"
#include "core/status_macros.h"
#include "proto/avatar_params_codec.h"
#include "proto/json_codec.h"
#include "services/cli_context.h"

namespace fitbase::services {
namespace {

struct AvatarFlags {
  std::string params = "{}";
  std::string out;
  bool full = false;
};

// JSON_OR_FILE: inline JSON starts with '{'; anything else is a file path.
absl::StatusOr<core::BodyParams> ParamsFromArgument(const std::string& argument) {
  const size_t first = argument.find_first_not_of(" \t\r\n");
  std::string json = argument;
  if (first == std::string::npos || argument[first] != '{') {
    ASSIGN_OR_RETURN(json, core::ReadFileToString(argument));
  }
  v1::AvatarParams message;
  RETURN_IF_ERROR(proto::ParseJson(json, &message));
  return proto::BodyParamsFromProto(message);
}

absl::Status RunAvatar(const CliContext& context, const AvatarFlags& flags) {
  ASSIGN_OR_RETURN(core::BodyParams params, ParamsFromArgument(flags.params));
  ASSIGN_OR_RETURN(core::BodyModel model, core::BodyModel::Load(ResolveDataDir(context)));
  ASSIGN_OR_RETURN(core::Mesh mesh, flags.full ? model.BuildFullMesh(params) : model.BuildBody(params));
  RETURN_IF_ERROR(core::WriteObj(flags.out, mesh));
  std::cout << "wrote " << flags.out << " (" << mesh.vertex_count() << " vertices, "
            << mesh.faces.face_count() << " faces, topology " << mesh.topology_id
            << ", meters)\n";
  return absl::OkStatus();
}

}  // namespace

void AddAvatarCommand(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<AvatarFlags>();
  CLI::App* command = app.add_subcommand("avatar", "Build one MakeHuman body avatar (meters)");
  command->add_option("--params", flags->params,
                      "AvatarParams as inline JSON or a JSON file; unset fields take "
                      "MakeHuman's defaults (default: {})");
  command->add_option("--out", flags->out, "Output OBJ (body: 13,380 vertices)")->required();
  command->add_flag("--full", flags->full,
                    "Write the whole 19,158-vertex hm08 mesh (with helpers) instead of the body");
  command->callback([&context, flags] {
    context.action = [&context, flags] { return RunAvatar(context, *flags); };
  });
}

}  // namespace fitbase::services
