// A body avatar OBJ as a shop or a population folder gives it: pipeline::ReadAvatarObj, which
// reads the file through OpenMesh (core::ReadObj) and then checks the hm08 body's vertex count
// and size. It reads a path, so each input goes through one temporary file.
#include <stdlib.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "OpenMesh/Core/System/omstream.hh"
#include "pipeline/avatar_file.h"

namespace {

class InputFile {
 public:
  InputFile() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "fitbase-fuzz-XXXXXX.obj").string();
    const int fd = mkstemps(pattern.data(), 4);
    if (fd < 0) std::abort();
    close(fd);
    path_ = pattern;
  }
  ~InputFile() {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }
  const std::filesystem::path& Write(const uint8_t* data, size_t size) {
    std::ofstream(path_, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    return path_;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // OpenMesh reports every unreadable line on its own streams; the status says it once.
  omerr().disable();
  omlog().disable();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static InputFile file;
  (void)fitbase::pipeline::ReadAvatarObj(file.Write(data, size));
  return 0;
}
