#ifndef FITBASE_PIPELINE_AVATAR_FILE_H_
#define FITBASE_PIPELINE_AVATAR_FILE_H_

#include <filesystem>

#include "absl/status/statusor.h"
#include "core/mesh.h"

namespace fitbase::pipeline {

// Reads a body avatar OBJ (topology makehuman-hm08-body, meters). Errors name the file and
// the problem: wrong vertex count, non-finite coordinates, a size that is not a human in
// meters (decimeter files from MakeHuman are the usual mistake).
absl::StatusOr<core::Mesh> ReadAvatarObj(const std::filesystem::path& path);

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_AVATAR_FILE_H_
