#include "cli/cli_context.h"

#include <cstdlib>

namespace fitbase::cli {

std::filesystem::path ResolveDataDir(const CliContext& context) {
  if (!context.data_dir.empty()) return context.data_dir;
  if (const char* env = std::getenv("FITBASE_DATA"); env != nullptr && *env != '\0') return env;
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path beside_build = exe.parent_path().parent_path() / "data/makehuman";
    if (std::filesystem::exists(beside_build / "base.obj")) return beside_build;
  }
  return "data/makehuman";
}

}  // namespace fitbase::cli
