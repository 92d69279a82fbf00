#include "pipeline/population_folder.h"

#include <algorithm>
#include <iostream>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_split.h"
#include "core/file_util.h"
#include "core/obj_io.h"
#include "core/status_macros.h"
#include "pipeline/avatar_file.h"
#include "pipeline/progress_reporter.h"
#include "proto/avatar_params_codec.h"
#include "proto/json_codec.h"

namespace fitbase::pipeline {
namespace {

constexpr char kProvenanceFile[] = "population.json";
constexpr char kParamsFile[] = "params.jsonl";

std::string AvatarFileName(int64_t index) { return absl::StrFormat("avatar-%05d.obj", index); }

// The avatar files named by population.json, or every *.obj in name order.
absl::StatusOr<std::vector<std::filesystem::path>> ListAvatarFiles(
    const std::filesystem::path& dir, const v1::PopulationProvenance* provenance) {
  std::vector<std::filesystem::path> files;
  if (provenance != nullptr) {
    for (uint32_t i = 0; i < provenance->count(); ++i) files.push_back(dir / AvatarFileName(i));
    return files;
  }
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.is_regular_file() && entry.path().extension() == ".obj")
      files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

absl::Status ReadParamsLines(const std::filesystem::path& path, v1::PopulationProvenance* out) {
  ASSIGN_OR_RETURN(std::string text, core::ReadFileToString(path));
  int line_number = 0;
  for (absl::string_view line : absl::StrSplit(text, '\n')) {
    ++line_number;
    if (absl::StripAsciiWhitespace(line).empty()) continue;
    v1::AvatarParams* params = out->add_params();
    absl::Status status = proto::ParseJson(line, params);
    if (status.ok()) status = proto::BodyParamsFromProto(*params).status();
    if (!status.ok()) {
      return absl::InvalidArgumentError(
          absl::StrCat(path.string(), " line ", line_number, ": ", status.message()));
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status WritePopulationFolder(const core::BodyModel& model, core::PopulationPreset preset,
                                   uint64_t seed, int64_t count,
                                   const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    return absl::InternalError(absl::StrCat("cannot create ", dir.string(), ": ", ec.message()));
  ProgressReporter progress("avatars", count, std::cerr, StderrIsTerminal());
  std::string params_lines;
  for (int64_t i = 0; i < count; ++i) {
    const core::BodyParams params = core::SampleBodyParams(preset, seed, static_cast<uint64_t>(i));
    ASSIGN_OR_RETURN(core::Mesh body, model.BuildBody(params));
    RETURN_IF_ERROR(core::WriteObj(dir / AvatarFileName(i), body));
    absl::StrAppend(&params_lines, proto::ToJson(proto::BodyParamsToProto(params)), "\n");
    progress.Update(i + 1);
  }
  progress.Finish();
  RETURN_IF_ERROR(core::WriteFileAtomically(dir / kParamsFile, params_lines));
  v1::PopulationProvenance provenance;
  provenance.set_preset(std::string(core::PopulationPresetName(preset)));
  provenance.set_seed(seed);
  provenance.set_count(static_cast<uint32_t>(count));
  return core::WriteFileAtomically(dir / kProvenanceFile, proto::ToJson(provenance) + "\n");
}

absl::StatusOr<Population> SamplePopulation(const core::BodyModel& model,
                                            core::PopulationPreset preset, uint64_t seed,
                                            int64_t count) {
  if (count < 2) {
    return absl::InvalidArgumentError(absl::StrCat("count ", count, ": a basis needs at least 2"));
  }
  Population population;
  population.provenance.set_preset(std::string(core::PopulationPresetName(preset)));
  population.provenance.set_seed(seed);
  population.provenance.set_count(static_cast<uint32_t>(count));
  population.samples.resize(3 * core::kBodyVertexCount, count);
  for (int64_t i = 0; i < count; ++i) {
    const core::BodyParams params = core::SampleBodyParams(preset, seed, static_cast<uint64_t>(i));
    ASSIGN_OR_RETURN(core::Mesh body, model.BuildBody(params));
    population.samples.col(i) =
        Eigen::Map<const Eigen::VectorXd>(body.positions.data(), body.positions.size());
    if (i == 0) population.faces = std::move(body.faces);
    *population.provenance.add_params() = proto::BodyParamsToProto(params);
  }
  return population;
}

absl::StatusOr<Population> ReadPopulationFolder(const std::filesystem::path& dir) {
  if (!std::filesystem::is_directory(dir)) {
    return absl::NotFoundError(absl::StrCat("no population folder ", dir.string()));
  }
  Population population;
  const bool has_provenance = std::filesystem::exists(dir / kProvenanceFile);
  if (has_provenance) {
    ASSIGN_OR_RETURN(std::string json, core::ReadFileToString(dir / kProvenanceFile));
    RETURN_IF_ERROR(proto::ParseJson(json, &population.provenance));
    if (population.provenance.params_size() != 0) {
      return absl::InvalidArgumentError(
          absl::StrCat(kProvenanceFile, " must not list params; they belong in ", kParamsFile));
    }
    RETURN_IF_ERROR(ReadParamsLines(dir / kParamsFile, &population.provenance));
    if (population.provenance.params_size() != static_cast<int>(population.provenance.count())) {
      return absl::InvalidArgumentError(absl::StrCat(
          (dir / kParamsFile).string(), " has ", population.provenance.params_size(),
          " lines but ", kProvenanceFile, " says count ", population.provenance.count()));
    }
  }
  ASSIGN_OR_RETURN(population.avatar_files,
                   ListAvatarFiles(dir, has_provenance ? &population.provenance : nullptr));
  const int64_t count = static_cast<int64_t>(population.avatar_files.size());
  if (count < 2) {
    return absl::InvalidArgumentError(
        absl::StrCat(dir.string(), " holds ", count, " avatars; a basis needs at least 2"));
  }
  population.samples.resize(3 * core::kBodyVertexCount, count);
  ProgressReporter progress("reading avatars", count, std::cerr, StderrIsTerminal());
  for (int64_t i = 0; i < count; ++i) {
    ASSIGN_OR_RETURN(core::Mesh avatar, ReadAvatarObj(population.avatar_files[i]));
    population.samples.col(i) =
        Eigen::Map<const Eigen::VectorXd>(avatar.positions.data(), avatar.positions.size());
    if (i == 0) {
      population.faces = std::move(avatar.faces);
    } else if (avatar.faces != population.faces) {
      return absl::InvalidArgumentError(absl::StrCat(population.avatar_files[i].string(),
                                                     " has other faces than ",
                                                     population.avatar_files[0].string()));
    }
    progress.Update(i + 1);
  }
  progress.Finish();
  population.provenance.set_count(static_cast<uint32_t>(count));
  return population;
}

}  // namespace fitbase::pipeline
