// fitbase avatar: one MakeHuman body from parameters; `avatar export` / `avatar import`
// convert between avatar OBJs and the common avatar format (docs/avatar-format.md).
#include <cmath>
#include <iostream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "body/body_measurements.h"
#include "body/body_model.h"
#include "cli/cli_context.h"
#include "core/file_util.h"
#include "core/obj_io.h"
#include "core/status_macros.h"
#include "pipeline/avatar_file.h"
#include "pipeline/avatar_from_measurements.h"
#include "pipeline/avatar_projection.h"
#include "proto/avatar_codec.h"
#include "proto/avatar_params_codec.h"
#include "proto/json_codec.h"
#include "proto/message_file.h"

namespace fitbase::cli {
namespace {

struct AvatarFlags {
  std::string params = "{}";
  std::string out;
  bool full = false;
};

struct ExportFlags {
  std::string obj;
  std::string params;
  bool draco = false;
  std::string out;
};

struct ImportFlags {
  std::string in;
  std::string out;
};

struct FromMeasurementsFlags {
  std::string basis;
  std::string measurements;
  std::string out;
  std::string weights;
};

struct MeasureFlags {
  std::string obj;
  bool json = false;
};

// JSON_OR_FILE: inline JSON starts with '{'; anything else is a file path.
absl::StatusOr<v1::AvatarParams> ParamsMessageFromArgument(const std::string& argument) {
  const size_t first = argument.find_first_not_of(" \t\r\n");
  std::string json = argument;
  if (first == std::string::npos || argument[first] != '{') {
    ASSIGN_OR_RETURN(json, core::ReadFileToString(argument));
  }
  v1::AvatarParams message;
  RETURN_IF_ERROR(proto::ParseJson(json, &message));
  return message;
}

absl::Status RunAvatar(const CliContext& context, const AvatarFlags& flags) {
  ASSIGN_OR_RETURN(v1::AvatarParams message, ParamsMessageFromArgument(flags.params));
  ASSIGN_OR_RETURN(body::BodyParams params, proto::BodyParamsFromProto(message));
  ASSIGN_OR_RETURN(body::BodyModel model, body::BodyModel::Load(ResolveDataDir(context)));
  ASSIGN_OR_RETURN(core::Mesh mesh,
                   flags.full ? model.BuildFullMesh(params) : model.BuildBody(params));
  RETURN_IF_ERROR(core::WriteObj(flags.out, mesh));
  std::cout << "wrote " << flags.out << " (" << mesh.vertex_count() << " vertices, "
            << mesh.faces.face_count() << " faces, topology " << mesh.topology_id
            << ", meters)\n";
  return absl::OkStatus();
}

absl::Status RunExport(const ExportFlags& flags) {
  ASSIGN_OR_RETURN(core::Mesh mesh, pipeline::ReadAvatarObj(flags.obj));
  v1::AvatarParams params;
  if (!flags.params.empty()) {
    ASSIGN_OR_RETURN(params, ParamsMessageFromArgument(flags.params));
  }
  ASSIGN_OR_RETURN(v1::Avatar avatar,
                   proto::AvatarFromPositions(mesh.positions, flags.draco,
                                              flags.params.empty() ? nullptr : &params));
  RETURN_IF_ERROR(proto::WriteMessageFile(flags.out, avatar));
  const v1::EncodedPositions& positions = avatar.positions();
  std::string encoding = "raw float32";
  if (positions.has_draco()) {
    encoding = absl::StrFormat("Draco %d bits, max error %.2f mm",
                               positions.draco().quantization_bits(),
                               1e3 * positions.draco().max_error_m());
  }
  std::cout << absl::StrFormat("wrote %s (format_version %d, %d vertices, %s, %d bytes)\n",
                               flags.out, avatar.format_version(), positions.vertex_count(),
                               encoding, avatar.ByteSizeLong());
  return absl::OkStatus();
}

absl::Status RunImport(const CliContext& context, const ImportFlags& flags) {
  v1::Avatar avatar;
  RETURN_IF_ERROR(proto::ReadMessageFile(flags.in, &avatar));
  auto positions = proto::AvatarPositions(avatar);
  if (!positions.ok()) {
    return absl::Status(positions.status().code(),
                        absl::StrCat(flags.in, ": ", positions.status().message()));
  }
  // The format carries no faces: every body of the topology has those of base.obj's body group.
  ASSIGN_OR_RETURN(core::Mesh base, core::ReadObj(ResolveDataDir(context) / "base.obj"));
  const core::Mesh mesh{.topology_id = std::string(body::kBodyTopologyId),
                        .positions = *std::move(positions),
                        .faces = body::BodyFacesOf(base.faces)};
  RETURN_IF_ERROR(core::WriteObj(flags.out, mesh));
  std::cout << "wrote " << flags.out << " (" << mesh.vertex_count() << " vertices, "
            << mesh.faces.face_count() << " faces, topology " << mesh.topology_id
            << ", meters)\n";
  return absl::OkStatus();
}

absl::Status RunMeasure(const MeasureFlags& flags) {
  ASSIGN_OR_RETURN(core::Mesh mesh, pipeline::ReadAvatarObj(flags.obj));
  auto measured = body::MeasureBody(mesh);
  if (!measured.ok()) {
    return absl::Status(measured.status().code(),
                        absl::StrCat(flags.obj, ": ", measured.status().message()));
  }
  if (flags.json) {
    std::string json = "{";
    for (body::Measurement m : body::AllMeasurements()) {
      absl::StrAppendFormat(&json, "%s\"%s_%s\": %.1f", json.size() > 1 ? ", " : "",
                            body::MeasurementName(m), body::TypedUnit(m),
                            body::InTypedUnit(m, (*measured)[static_cast<int>(m)]));
    }
    std::cout << json << "}\n";
    return absl::OkStatus();
  }
  for (body::Measurement m : body::AllMeasurements()) {
    std::cout << absl::StrFormat("%-16s %7.1f %s\n", body::MeasurementName(m),
                                 body::InTypedUnit(m, (*measured)[static_cast<int>(m)]),
                                 body::TypedUnit(m));
  }
  return absl::OkStatus();
}

absl::Status RunFromMeasurements(const FromMeasurementsFlags& flags) {
  ASSIGN_OR_RETURN(const std::string json, core::ReadFileToString(flags.measurements));
  v1::TypedMeasurements typed;
  if (absl::Status parsed = proto::ParseJson(json, &typed); !parsed.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(flags.measurements, ": ", parsed.message()));
  }
  auto given = pipeline::MeasurementsFromProto(typed);
  if (!given.ok()) {
    return absl::Status(given.status().code(),
                        absl::StrCat(flags.measurements, ": ", given.status().message()));
  }
  ASSIGN_OR_RETURN(const pipeline::LoadedAvatarBasis basis, pipeline::LoadAvatarBasis(flags.basis));
  ASSIGN_OR_RETURN(const pipeline::MeasurementModel model,
                   pipeline::MeasurementModel::Build(basis));
  ASSIGN_OR_RETURN(const pipeline::MeasuredAvatar made,
                   pipeline::AvatarFromMeasurements(basis, model, *given));
  RETURN_IF_ERROR(core::WriteObj(flags.out, made.avatar));
  if (!flags.weights.empty()) {
    v1::AvatarWeights weights;
    weights.set_basis_id(basis.message.id());
    for (double w : made.weights) weights.add_weights(w);
    RETURN_IF_ERROR(core::WriteFileAtomically(flags.weights, proto::ToJson(weights) + "\n"));
  }
  for (const auto& [measurement, given_value, reached] : made.residuals) {
    const absl::string_view unit = body::TypedUnit(measurement);
    std::cout << absl::StrFormat(
        "%-18s %7.1f %s given, %7.1f %s reached%s\n", body::MeasurementName(measurement),
        body::InTypedUnit(measurement, given_value), unit,
        body::InTypedUnit(measurement, reached), unit,
        std::abs(reached - given_value) <= pipeline::MeasurementAllowance(measurement)
            ? ""
            : "  (outside ISO 20685-1's allowance)");
  }
  for (const std::string& reason : made.out_of_distribution_reasons) {
    std::cout << "out of distribution: " << reason << "\n";
  }
  std::cout << "wrote " << flags.out << " (basis " << basis.message.id() << ", "
            << made.weights.size() << " weights)\n";
  return absl::OkStatus();
}

void AddFromMeasurementsCommand(CLI::App& avatar, CliContext& context) {
  auto flags = std::make_shared<FromMeasurementsFlags>();
  CLI::App* command = avatar.add_subcommand(
      "from-measurements",
      "Make the basis's body that best matches a person's measurements (cm, kg)");
  command->add_option("--basis", flags->basis, "Avatar basis (.fbb)")->required();
  command->add_option("--measurements", flags->measurements,
                      "JSON: any of the keys `avatar measure --json` prints, stature_cm at least")
      ->required();
  command->add_option("--out", flags->out, "Output avatar OBJ (meters)")->required();
  command->add_option("--weights", flags->weights,
                      "Also write the weights as JSON (what `fit --weights` reads)");
  command->callback([&context, flags] {
    context.action = [flags] { return RunFromMeasurements(*flags); };
  });
}

void AddMeasureCommand(CLI::App& avatar, CliContext& context) {
  auto flags = std::make_shared<MeasureFlags>();
  CLI::App* command = avatar.add_subcommand(
      "measure", "Take a body's tailor's measurements (ISO 8559-1, README): cm and kg");
  command->add_option("obj", flags->obj, "Avatar OBJ (13,380 vertices, meters)")->required();
  command->add_flag("--json", flags->json,
                    "One JSON object, keys <measurement>_cm and weight_kg (what "
                    "`avatar from-measurements` reads)");
  command->callback([&context, flags] {
    context.action = [flags] { return RunMeasure(*flags); };
  });
}

void AddExportCommand(CLI::App& avatar, CliContext& context) {
  auto flags = std::make_shared<ExportFlags>();
  CLI::App* command = avatar.add_subcommand(
      "export", "Write an avatar OBJ as a common-format Avatar message (docs/avatar-format.md)");
  command->add_option("--obj", flags->obj, "Avatar OBJ (13,380 vertices, meters)")->required();
  command->add_option("--params", flags->params,
                      "The AvatarParams that made it, as inline JSON or a JSON file (optional)");
  command->add_flag("--draco", flags->draco,
                    "Draco-compress the positions (11 bits, about 0.4 mm) instead of raw float32");
  command->add_option("--out", flags->out, "Output Avatar message file (.fba)")->required();
  command->callback([&context, flags] {
    context.action = [flags] { return RunExport(*flags); };
  });
}

void AddImportCommand(CLI::App& avatar, CliContext& context) {
  auto flags = std::make_shared<ImportFlags>();
  CLI::App* command = avatar.add_subcommand(
      "import", "Validate a common-format Avatar message and write it as an avatar OBJ");
  command->add_option("--in", flags->in, "Avatar message file (.fba)")->required();
  command->add_option("--out", flags->out, "Output OBJ (13,380 vertices, body faces, meters)")
      ->required();
  command->callback([&context, flags] {
    context.action = [&context, flags] { return RunImport(context, *flags); };
  });
}

}  // namespace

void AddAvatarCommand(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<AvatarFlags>();
  CLI::App* command = app.add_subcommand(
      "avatar",
      "Build one MakeHuman body avatar (meters); export/import the common format; measure one");
  command->require_subcommand(0, 1);
  command->add_option("--params", flags->params,
                      "AvatarParams as inline JSON or a JSON file; unset fields take "
                      "MakeHuman's defaults (default: {})");
  command->add_option("--out", flags->out,
                      "Output OBJ (body: 13,380 vertices); required unless export or import");
  command->add_flag("--full", flags->full,
                    "Write the whole 19,158-vertex hm08 mesh (with helpers) instead of the body");
  AddExportCommand(*command, context);
  AddImportCommand(*command, context);
  AddMeasureCommand(*command, context);
  AddFromMeasurementsCommand(*command, context);
  // Runs after a subcommand's callback, which has then set the action.
  command->callback([&context, flags, command] {
    if (!command->get_subcommands().empty()) return;
    if (flags->out.empty()) throw CLI::RequiredError("--out");
    context.action = [&context, flags] { return RunAvatar(context, *flags); };
  });
}

}  // namespace fitbase::cli
