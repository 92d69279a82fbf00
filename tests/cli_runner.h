#ifndef FITBASE_TESTS_CLI_RUNNER_H_
#define FITBASE_TESTS_CLI_RUNNER_H_

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "core/file_util.h"
#include "core/test_support.h"

namespace fitbase {

namespace fs = std::filesystem;

// What a run of the binary printed.
struct Result {
  int exit_code;
  std::string out;
  std::string err;
};

// An empty folder `name` in this process's temporary folder.
inline fs::path Scratch(const std::string& name) {
  const fs::path dir = core::ProcessTempDir() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

inline std::string Quote(const std::string& arg) {
  std::string quoted = "'";
  for (char c : arg) quoted += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// Runs the real `fitbase` binary (with the test data folder) and captures what it printed.
inline Result RunFitbase(const std::vector<std::string>& args) {
  static int calls = 0;
  const fs::path dir = core::ProcessTempDir();
  fs::create_directories(dir);
  const fs::path out = dir / absl::StrCat("out", calls, ".txt");
  const fs::path err = dir / absl::StrCat("err", calls++, ".txt");
  std::vector<std::string> quoted = {FITBASE_BINARY, "--data", core::TestDataDir().string()};
  quoted.insert(quoted.end(), args.begin(), args.end());
  for (std::string& a : quoted) a = Quote(a);
  const std::string command = absl::StrCat(absl::StrJoin(quoted, " "), " >", out.string(), " 2>",
                                           err.string(), " </dev/null");
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, *core::ReadFileToString(out),
          *core::ReadFileToString(err)};
}

}  // namespace fitbase

#endif  // FITBASE_TESTS_CLI_RUNNER_H_
