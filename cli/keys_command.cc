// fitbase keys add: a new API key for the servers.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "cli/api_key_source.h"
#include "cli/cli_context.h"
#include "core/file_util.h"
#include "core/status_macros.h"
#include "services/rpc/api_keys.h"

namespace fitbase::cli {
namespace {

struct KeysAddFlags {
  std::string file;
  std::string tenant;
  std::string role;
};

// Appends `bytes` to `path` and syncs them, so a key once shown is not lost in a crash.
// A new file (`create`) is readable by its owner only: it says which tenants and roles exist.
absl::Status AppendToKeyFile(const std::filesystem::path& path, bool create,
                             absl::string_view bytes) {
  const int fd =
      ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC | (create ? O_CREAT | O_EXCL : 0), 0600);
  if (fd < 0) return absl::ErrnoToStatus(errno, absl::StrCat("cannot open ", path.string()));
  while (!bytes.empty()) {
    const ssize_t written = ::write(fd, bytes.data(), bytes.size());
    if (written < 0 && errno == EINTR) continue;
    if (written < 0) {
      const int error = errno;
      ::close(fd);
      return absl::ErrnoToStatus(error, absl::StrCat("cannot write ", path.string()));
    }
    bytes.remove_prefix(static_cast<size_t>(written));
  }
  int error = ::fsync(fd) == 0 ? 0 : errno;
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) return absl::ErrnoToStatus(error, absl::StrCat("cannot write ", path.string()));
  return absl::OkStatus();
}

absl::Status RunKeysAdd(const KeysAddFlags& flags) {
  RETURN_IF_ERROR(rpc::ValidateTenantId(flags.tenant));
  ASSIGN_OR_RETURN(const rpc::Role role, rpc::ParseRole(flags.role));
  const std::filesystem::path path = flags.file;
  std::error_code ec;
  const bool exists = std::filesystem::exists(path, ec);
  if (ec) {
    return absl::InternalError(absl::StrCat("cannot stat ", path.string(), ": ", ec.message()));
  }
  std::string line;
  if (exists) {
    ASSIGN_OR_RETURN(const std::string text, core::ReadFileToString(path));
    // Else the key would be shown, yet no server could load the file to accept it.
    if (const absl::StatusOr<rpc::ApiKeyRegistry> registry =
            rpc::ApiKeyRegistry::Parse(text, path.string());
        !registry.ok()) {
      return absl::FailedPreconditionError(absl::StrCat(
          "not adding a key to a file that does not load: ", registry.status().message()));
    }
    if (!text.empty() && text.back() != '\n') line = "\n";
  }
  ASSIGN_OR_RETURN(const std::string key, rpc::NewApiKey());
  absl::StrAppend(&line, rpc::HashApiKey(key), " ", flags.tenant, " ", rpc::RoleName(role), "\n");
  RETURN_IF_ERROR(AppendToKeyFile(path, !exists, line));
  std::cout << key << std::endl;
  std::cerr << "added to " << path.string() << ": a key of tenant " << flags.tenant << ", role "
            << rpc::RoleName(role)
            << ". This is the only time the key is shown: keep it secret, and "
            << "give it to clients in $" << kApiKeyVariable << ".\n";
  return absl::OkStatus();
}

}  // namespace

void AddKeysCommand(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<KeysAddFlags>();
  CLI::App* keys = app.add_subcommand("keys", "API keys of the servers");
  keys->require_subcommand(1);
  CLI::App* add = keys->add_subcommand(
      "add", "Make a new API key, add its hash to a key file and print the key once");
  add->add_option("--file", flags->file,
                  "Key file: '<sha256 hex> <tenant> <role>' lines (created mode 0600)")
      ->required();
  add->add_option("--tenant", flags->tenant, "The tenant the key acts for")->required();
  add->add_option("--role", flags->role, "customer, ingestion, admin or worker")->required();
  add->callback([&context, flags] { context.action = [flags] { return RunKeysAdd(*flags); }; });
}

}  // namespace fitbase::cli
