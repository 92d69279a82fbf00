// The API key file a server loads at startup: rpc::ApiKeyRegistry::Parse, then a lookup.
#include <cstdint>

#include "absl/strings/string_view.h"
#include "services/rpc/api_keys.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto registry = fitbase::rpc::ApiKeyRegistry::Parse(
      absl::string_view(reinterpret_cast<const char*>(data), size), "fuzz input");
  if (registry.ok()) (void)registry->Authenticate("fb_not_a_listed_key");
  return 0;
}
