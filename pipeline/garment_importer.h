#ifndef FITBASE_PIPELINE_GARMENT_IMPORTER_H_
#define FITBASE_PIPELINE_GARMENT_IMPORTER_H_

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "body/body_model.h"
#include "fitbase/v1/avatar_basis.pb.h"
#include "fitbase/v1/garment.pb.h"

namespace fitbase::pipeline {

// A garment file's contents, so a server imports an upload without writing it to disk.
struct SourceFile {
  // Its path or upload name: errors name it, a garment records its .mhclo's (or placed OBJ's)
  // name as its source path, and that name's stem is the default garment name.
  std::string name;
  std::string bytes;
};

struct GarmentImportRequest {
  // The garment's OBJ. With `mhclo`, the OBJ that binding binds (the file its obj_file line
  // names, in data units); without, an OBJ already placed on the basis's mean avatar (meters).
  SourceFile obj;
  std::optional<SourceFile> mhclo;  // A MakeHuman binding to the hm08 mesh (.mhclo).
  std::string name;                 // Default: the stem of the .mhclo's name, else the OBJ's.
  std::vector<std::string> sizes;   // Graded from the template; M is the template's size.
  // The ease it is cut with, for size advice ("knit", "fitted", "shirt", "jacket"; empty is
  // "shirt"). Not part of the garment's id: it changes no drape.
  std::string garment_type;
  // Retailer-supplied rest meshes by size name (same topology as the garment), meters; every
  // one for a size in `sizes`.
  std::map<std::string, SourceFile> size_meshes;
  // Which openings are elastic cuffs (none by default). Part of the id when any is declared.
  v1::ElasticCuffs cuffs;
};

// The cuffs a comma-separated list names: "sleeves", "legs", both, or "none" (or nothing).
// INVALID_ARGUMENT naming any other word or a repeated one.
absl::StatusOr<v1::ElasticCuffs> ParseCuffs(absl::string_view list);

// Whether `cuffs` declares any: only then is it stored and part of the garment's id.
bool DeclaresCuffs(const v1::ElasticCuffs& cuffs);

// Where a garment's files are on disk, as `fitbase garment import` names them.
struct GarmentImportPaths {
  // Exactly one of: a MakeHuman .mhclo (its OBJ is the file its obj_file line names, beside
  // it), or an OBJ already placed on the basis's mean avatar.
  std::filesystem::path mhclo;
  std::filesystem::path obj;
  std::map<std::string, std::filesystem::path> size_meshes;
};

// Reads the files into a request, each named by its path (name and sizes are left empty).
// Errors: not exactly one of mhclo and obj, a .mhclo that does not parse or names no OBJ, a
// missing file (NOT_FOUND).
absl::StatusOr<GarmentImportRequest> ReadGarmentImportFiles(const GarmentImportPaths& paths);

// The full 19,158-vertex mean avatar of a basis: the mean of the full meshes of its training
// avatars, rebuilt from their parameters (so helpers and joints are exact, and the body part
// equals the basis mean). FAILED_PRECONDITION for a basis without avatar parameters.
absl::StatusOr<core::Mesh> MeanFullAvatar(const body::BodyModel& model,
                                          const v1::AvatarBasis& basis);

// The content hash of a request's garment files: its OBJ, then its binding if it has one.
std::string SourceSha256(const GarmentImportRequest& request);

// The id ImportGarment gives the garment of `request` on the basis `basis_id`, without
// importing it: the importer's version, the basis, the files' bytes, the sizes and the
// declared cuffs (a garment without cuffs keeps the id it had before they existed). NOT_FOUND
// for an unknown size name without a mesh.
absl::StatusOr<std::string> GarmentImportId(absl::string_view basis_id,
                                            const GarmentImportRequest& request);

// Imports a garment: places it on the basis's mean avatar (by its binding, or as given),
// pushes it out of the body and relaxes it into the template, and records its sizes, the
// body axes and regions it covers, and its binding. The id hashes the basis, the files'
// bytes (not their names) and the sizes. Errors name the file and the problem: a file that
// does not parse, OBJ and binding vertex counts that disagree, a size mesh of another topology
// or for a size not in `sizes`, no sizes, a placed OBJ not in meters (INVALID_ARGUMENT); an
// unknown size name (NOT_FOUND); a basis without avatar parameters (FAILED_PRECONDITION).
absl::StatusOr<v1::Garment> ImportGarment(const body::BodyModel& model,
                                          const v1::AvatarBasis& basis,
                                          const GarmentImportRequest& request);

// The grading step of a standard size name (M = 0, L = 1, S = -1, ...), or NOT_FOUND.
absl::StatusOr<int> GradingStep(absl::string_view size);

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_GARMENT_IMPORTER_H_
