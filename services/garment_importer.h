#ifndef FITBASE_SERVICES_GARMENT_IMPORTER_H_
#define FITBASE_SERVICES_GARMENT_IMPORTER_H_

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "core/body_model.h"
#include "fitbase/v1/avatar_basis.pb.h"
#include "fitbase/v1/garment.pb.h"

namespace fitbase::services {

struct GarmentImportRequest {
  // Exactly one of: a MakeHuman .mhclo (its OBJ is found beside it), or an OBJ already placed
  // on the basis's mean avatar (meters).
  std::filesystem::path mhclo;
  std::filesystem::path obj;
  std::string name;                     // Default: the file's stem.
  std::vector<std::string> sizes;       // Graded from the template; M is the template's size.
  // Retailer-supplied rest meshes by size name (same topology as the garment), meters.
  std::map<std::string, std::filesystem::path> size_meshes;
};

// The full 19,158-vertex mean avatar of a basis: the mean of the full meshes of its training
// avatars, rebuilt from their parameters (so helpers and joints are exact, and the body part
// equals the basis mean). FAILED_PRECONDITION for a basis without avatar parameters.
absl::StatusOr<core::Mesh> MeanFullAvatar(const core::BodyModel& model,
                                          const v1::AvatarBasis& basis);

// Imports a garment: places it on the basis's mean avatar (by its binding, or as given),
// pushes it out of the body and relaxes it into the template, and records its sizes, the
// body axes and regions it covers, and its binding. Errors name the file and the problem
// (vertex counts of OBJ and binding disagree, unknown size name, non-finite positions, ...).
absl::StatusOr<v1::Garment> ImportGarment(const core::BodyModel& model,
                                          const v1::AvatarBasis& basis,
                                          const GarmentImportRequest& request);

// The grading step of a standard size name (M = 0, L = 1, S = -1, ...), or NOT_FOUND.
absl::StatusOr<int> GradingStep(absl::string_view size);

}  // namespace fitbase::services

#endif  // FITBASE_SERVICES_GARMENT_IMPORTER_H_
