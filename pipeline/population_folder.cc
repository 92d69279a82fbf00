#include "pipeline/population_folder.h"

#include <algorithm>
#include <cmath>
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

absl::Status WritePopulationFolder(const body::BodyModel& model, body::PopulationPreset preset,
                                   uint64_t seed, int64_t count,
                                   const std::filesystem::path& dir,
                                   std::vector<body::CalibratedAvatar>* calibration) {
  ASSIGN_OR_RETURN(const body::PopulationSampler sampler, body::PopulationSampler::Create(model));
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    return absl::InternalError(absl::StrCat("cannot create ", dir.string(), ": ", ec.message()));
  ProgressReporter progress("avatars", count, std::cerr, StderrIsTerminal());
  std::string params_lines;
  for (int64_t i = 0; i < count; ++i) {
    body::BodyParams params;
    if (body::IsCalibratedPreset(preset)) {
      ASSIGN_OR_RETURN(body::CalibratedAvatar avatar,
                       sampler.SampleCalibrated(preset, seed, static_cast<uint64_t>(i)));
      params = avatar.params;
      if (calibration != nullptr) calibration->push_back(std::move(avatar));
    } else {
      params = body::SampleBodyParams(preset, seed, static_cast<uint64_t>(i));
    }
    ASSIGN_OR_RETURN(core::Mesh body, model.BuildBody(params));
    RETURN_IF_ERROR(core::WriteObj(dir / AvatarFileName(i), body));
    absl::StrAppend(&params_lines, proto::ToJson(proto::BodyParamsToProto(params)), "\n");
    progress.Update(i + 1);
  }
  progress.Finish();
  RETURN_IF_ERROR(core::WriteFileAtomically(dir / kParamsFile, params_lines));
  v1::PopulationProvenance provenance;
  provenance.set_preset(std::string(body::PopulationPresetName(preset)));
  provenance.set_seed(seed);
  provenance.set_count(static_cast<uint32_t>(count));
  return core::WriteFileAtomically(dir / kProvenanceFile, proto::ToJson(provenance) + "\n");
}

absl::StatusOr<Population> SamplePopulation(const body::BodyModel& model,
                                            body::PopulationPreset preset, uint64_t seed,
                                            int64_t count) {
  if (count < 2) {
    return absl::InvalidArgumentError(absl::StrCat("count ", count, ": a basis needs at least 2"));
  }
  Population population;
  population.provenance.set_preset(std::string(body::PopulationPresetName(preset)));
  population.provenance.set_seed(seed);
  population.provenance.set_count(static_cast<uint32_t>(count));
  population.samples.resize(3 * body::kBodyVertexCount, count);
  ASSIGN_OR_RETURN(const body::PopulationSampler sampler, body::PopulationSampler::Create(model));
  for (int64_t i = 0; i < count; ++i) {
    ASSIGN_OR_RETURN(const body::BodyParams params,
                     sampler.Sample(preset, seed, static_cast<uint64_t>(i)));
    ASSIGN_OR_RETURN(core::Mesh body, model.BuildBody(params));
    population.samples.col(i) =
        Eigen::Map<const Eigen::VectorXd>(body.positions.data(), body.positions.size());
    if (i == 0) population.faces = std::move(body.faces);
    *population.provenance.add_params() = proto::BodyParamsToProto(params);
  }
  return population;
}

std::string CalibrationTable(const std::vector<body::CalibratedAvatar>& avatars) {
  constexpr int kN = body::kSurveyMeasurementCount;
  const std::array<double, kN> allowance = {0.004, 0.5, 0.009, 0.009, 0.009};
  std::string table;
  for (const body::SurveyTable* survey : {&body::AnsurWomen(), &body::AnsurMen()}) {
    const bool women = survey == &body::AnsurWomen();
    std::vector<const body::CalibratedAvatar*> group;
    for (const body::CalibratedAvatar& avatar : avatars) {
      if ((avatar.params.gender < 0.5) == women) group.push_back(&avatar);
    }
    if (group.size() < 2) continue;
    absl::StrAppendFormat(&table,
                          "%s against %d avatars\n\n| measurement | survey mean | survey SD | "
                          "mean | SD | mean miss / survey SD | SD / survey SD | within allowance |\n"
                          "|---|---|---|---|---|---|---|---|\n",
                          survey->name, group.size());
    for (int k = 0; k < kN; ++k) {
      const double unit = body::InTypedUnit(body::kSurveyMeasurements[k], 1.0);
      double sum = 0, squares = 0;
      int within = 0;
      for (const body::CalibratedAvatar* avatar : group) {
        sum += avatar->measured[k];
        within += std::abs(avatar->measured[k] - avatar->target[k]) <= allowance[k];
      }
      const double mean = sum / static_cast<double>(group.size());
      for (const body::CalibratedAvatar* avatar : group) {
        squares += (avatar->measured[k] - mean) * (avatar->measured[k] - mean);
      }
      const double sd = std::sqrt(squares / static_cast<double>(group.size() - 1));
      absl::StrAppendFormat(&table, "| %s | %.1f | %.1f | %.1f | %.1f | %+.2f | %.2f | %.1f%% |\n",
                            body::MeasurementName(body::kSurveyMeasurements[k]),
                            unit * survey->mean[k], unit * survey->sd[k], unit * mean, unit * sd,
                            (mean - survey->mean[k]) / survey->sd[k], sd / survey->sd[k],
                            100.0 * within / static_cast<double>(group.size()));
    }
    // Correlations: the survey's against the population's, the largest difference named.
    double worst = 0;
    std::string worst_pair;
    for (int a = 0; a < kN; ++a) {
      for (int b = a + 1; b < kN; ++b) {
        double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
        for (const body::CalibratedAvatar* avatar : group) {
          const double x = avatar->measured[a], y = avatar->measured[b];
          sa += x;
          sb += y;
          saa += x * x;
          sbb += y * y;
          sab += x * y;
        }
        const double n = static_cast<double>(group.size());
        const double r = (sab - sa * sb / n) /
                         std::sqrt((saa - sa * sa / n) * (sbb - sb * sb / n));
        if (std::abs(r - survey->correlation[a][b]) > worst) {
          worst = std::abs(r - survey->correlation[a][b]);
          worst_pair = absl::StrFormat(
              "%s-%s: survey %.2f, population %.2f",
              body::MeasurementName(body::kSurveyMeasurements[a]),
              body::MeasurementName(body::kSurveyMeasurements[b]), survey->correlation[a][b], r);
        }
      }
    }
    absl::StrAppendFormat(&table, "\nCorrelations: largest difference %.2f (%s).\n\n", worst,
                          worst_pair);
  }
  return table;
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
  population.samples.resize(3 * body::kBodyVertexCount, count);
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
