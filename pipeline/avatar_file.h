#ifndef FITBASE_PIPELINE_AVATAR_FILE_H_
#define FITBASE_PIPELINE_AVATAR_FILE_H_

#include <filesystem>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "core/mesh.h"

namespace fitbase::pipeline {

// Reads a body avatar OBJ (topology makehuman-hm08-body, meters). Errors name the file and
// the problem: wrong vertex count, non-finite coordinates, a size that is not a human in
// meters (decimeter files from MakeHuman are the usual mistake).
absl::StatusOr<core::Mesh> ReadAvatarObj(const std::filesystem::path& path);

// The same for an OBJ's text (an upload), named `name` in errors.
absl::StatusOr<core::Mesh> ParseAvatarObj(absl::string_view text, absl::string_view name);

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_AVATAR_FILE_H_
