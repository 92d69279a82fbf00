#ifndef FITBASE_CORE_TEST_SUPPORT_H_
#define FITBASE_CORE_TEST_SUPPORT_H_

#include <stdlib.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::core {

// The MakeHuman data folder the build was configured with (scripts/setup.sh provides it).
inline std::filesystem::path TestDataDir() { return FITBASE_DATA_DIR; }

// A fresh folder under ::testing::TempDir(), unique to this process and removed at exit:
// ctest runs every test in its own process, in parallel, so fixed names would collide.
inline const std::filesystem::path& ProcessTempDir() {
  struct Dir {
    Dir() {
      std::string pattern =
          (std::filesystem::path(::testing::TempDir()) / "fitbase-XXXXXX").string();
      if (mkdtemp(pattern.data()) == nullptr) std::abort();
      path = pattern;
    }
    ~Dir() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
    std::filesystem::path path;
  };
  static const Dir dir;
  return dir.path;
}

inline const absl::Status& StatusOf(const absl::Status& status) { return status; }
template <typename T>
const absl::Status& StatusOf(const absl::StatusOr<T>& status_or) {
  return status_or.status();
}

// Matches an absl::Status or StatusOr with `code` whose message contains `substring`.
MATCHER_P2(StatusIs, code, substring, "") {
  const absl::Status& status = ::fitbase::core::StatusOf(arg);
  *result_listener << "status is " << status;
  return status.code() == code &&
         std::string(status.message()).find(substring) != std::string::npos;
}

}  // namespace fitbase::core

#endif  // FITBASE_CORE_TEST_SUPPORT_H_
