#ifndef FITBASE_PIPELINE_POPULATION_FOLDER_H_
#define FITBASE_PIPELINE_POPULATION_FOLDER_H_

#include <cstdint>
#include <filesystem>
#include <vector>

#include "Eigen/Core"
#include "absl/status/statusor.h"
#include "body/body_model.h"
#include "body/population_calibration.h"
#include "body/population_sampler.h"
#include "fitbase/v1/avatar_basis.pb.h"

namespace fitbase::pipeline {

// A population folder holds:
//   population.json  the PopulationProvenance (preset, seed, count), without params;
//   params.jsonl     one AvatarParams JSON per avatar, in order;
//   avatar-NNNNN.obj one body avatar per line of params.jsonl (meters).
// A folder of OBJ avatars from elsewhere (no population.json) is read in file-name order.

// Samples `count` avatars of (preset, seed) (body::PopulationSampler), builds their bodies
// and writes the folder, showing progress on stderr. For a calibrated preset, `calibration`
// (when given) receives each avatar's survey target and measurements.
absl::Status WritePopulationFolder(const body::BodyModel& model, body::PopulationPreset preset,
                                   uint64_t seed, int64_t count,
                                   const std::filesystem::path& dir,
                                   std::vector<body::CalibratedAvatar>* calibration = nullptr);

// How a calibrated population reproduces its survey, as a Markdown table per sex: each
// measurement's survey mean and SD against the population's (cm, kg), the mean's miss and the
// SD's in units of the survey's SD, and the share of avatars within ISO 20685-1's allowance of
// their drawn target (stature 4 mm, large girths 9 mm; weight 0.5 kg).
std::string CalibrationTable(const std::vector<body::CalibratedAvatar>& avatars);

struct Population {
  v1::PopulationProvenance provenance;  // With params when params.jsonl exists.
  std::vector<std::filesystem::path> avatar_files;
  Eigen::MatrixXd samples;  // 3V x K, flattened avatars (xyz interleaved), meters.
  core::PolygonFaces faces;
};

// The population WritePopulationFolder would write, in memory and without rounding the
// avatars to the folder's OBJ precision (so its basis id differs from the folder's).
absl::StatusOr<Population> SamplePopulation(const body::BodyModel& model,
                                            body::PopulationPreset preset, uint64_t seed,
                                            int64_t count);

// Reads and validates every avatar of the folder (vertex counts, finiteness, units).
absl::StatusOr<Population> ReadPopulationFolder(const std::filesystem::path& dir);

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_POPULATION_FOLDER_H_
