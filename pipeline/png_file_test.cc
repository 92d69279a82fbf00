#include "pipeline/png_file.h"

#include <png.h>

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "core/file_util.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::pipeline {
namespace {

uint32_t BigEndian32(const std::string& bytes, size_t at) {
  return (uint32_t{static_cast<uint8_t>(bytes[at])} << 24) |
         (uint32_t{static_cast<uint8_t>(bytes[at + 1])} << 16) |
         (uint32_t{static_cast<uint8_t>(bytes[at + 2])} << 8) |
         uint32_t{static_cast<uint8_t>(bytes[at + 3])};
}

TEST(PngFileTest, WritesRgbThatLibpngReadsBack) {
  const int width = 5;
  const int height = 3;
  std::vector<uint8_t> rgb(3 * width * height);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<uint8_t>(17 * i);
  const auto path = core::ProcessTempDir() / "image.png";
  ASSERT_TRUE(WritePng(path, width, height, rgb).ok());

  const absl::StatusOr<std::string> bytes = core::ReadFileToString(path);
  ASSERT_TRUE(bytes.ok());
  ASSERT_GE(bytes->size(), 24u);
  EXPECT_EQ(bytes->substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(bytes->substr(12, 4), "IHDR");
  EXPECT_EQ(BigEndian32(*bytes, 16), 5u);
  EXPECT_EQ(BigEndian32(*bytes, 20), 3u);

  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  ASSERT_TRUE(png_image_begin_read_from_memory(&image, bytes->data(), bytes->size()));
  image.format = PNG_FORMAT_RGB;
  std::vector<uint8_t> read(PNG_IMAGE_SIZE(image));
  ASSERT_TRUE(png_image_finish_read(&image, nullptr, read.data(), 0, nullptr));
  EXPECT_EQ(read, rgb);
}

TEST(PngFileTest, ErrorsNameThePath) {
  const std::vector<uint8_t> rgb(3 * 4, 0);
  const auto path = core::ProcessTempDir() / "wrong.png";
  const absl::Status wrong_size = WritePng(path, 3, 1, rgb);
  EXPECT_EQ(wrong_size.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(wrong_size.message(), testing::HasSubstr(path.string()));
  EXPECT_EQ(WritePng(path, 0, 1, {}).code(), absl::StatusCode::kInvalidArgument);

  const auto unwritable = core::ProcessTempDir() / "no-such-dir" / "image.png";
  const absl::Status missing_dir = WritePng(unwritable, 2, 2, rgb);
  EXPECT_FALSE(missing_dir.ok());
  EXPECT_THAT(missing_dir.message(), testing::HasSubstr("no-such-dir"));
}

}  // namespace
}  // namespace fitbase::pipeline
