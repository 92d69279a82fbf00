#include "pipeline/png_file.h"

#include <png.h>

#include <string>

#include "absl/strings/str_cat.h"
#include "core/file_util.h"

namespace fitbase::pipeline {

absl::Status WritePng(const std::filesystem::path& path, int width, int height,
                      const std::vector<uint8_t>& rgb) {
  constexpr int kMaxSide = 65535;
  if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide) {
    return absl::InvalidArgumentError(absl::StrCat("PNG ", path.string(), ": size ", width, "x",
                                                   height, " is outside [1, ", kMaxSide, "]"));
  }
  const size_t expected = 3 * static_cast<size_t>(width) * height;
  if (rgb.size() != expected) {
    return absl::InvalidArgumentError(absl::StrCat("PNG ", path.string(), ": ", rgb.size(),
                                                   " bytes for ", width, "x", height,
                                                   " RGB, expected ", expected));
  }
  // libpng's simplified API reports errors in `message` instead of longjmp-ing through C++.
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&image, nullptr, &size, 0, rgb.data(), 0, nullptr)) {
    return absl::InternalError(absl::StrCat("PNG ", path.string(), ": ", image.message));
  }
  std::string bytes(size, '\0');
  if (!png_image_write_to_memory(&image, bytes.data(), &size, 0, rgb.data(), 0, nullptr)) {
    return absl::InternalError(absl::StrCat("PNG ", path.string(), ": ", image.message));
  }
  bytes.resize(size);
  return core::WriteFileAtomically(path, bytes);
}

}  // namespace fitbase::pipeline
