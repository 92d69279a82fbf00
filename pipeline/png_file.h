#ifndef FITBASE_PIPELINE_PNG_FILE_H_
#define FITBASE_PIPELINE_PNG_FILE_H_

#include <cstdint>
#include <filesystem>
#include <vector>

#include "absl/status/status.h"

namespace fitbase::pipeline {

// Writes an 8-bit RGB PNG through libpng, to a temporary name renamed into place so readers
// never see half an image. `rgb` holds height x width x 3 bytes, rows from the top. Errors
// (naming `path`): a size outside [1, 65535] or not matching `rgb` (INVALID_ARGUMENT), libpng's
// or the file system's failure.
absl::Status WritePng(const std::filesystem::path& path, int width, int height,
                      const std::vector<uint8_t>& rgb);

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_PNG_FILE_H_
