// A MakeHuman `.target` morph target: core::ParseTarget against the full hm08 mesh, as the
// body model loads them.
#include <cstdint>

#include "absl/strings/string_view.h"
#include "core/body_model.h"
#include "core/target_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)fitbase::core::ParseTarget(absl::string_view(reinterpret_cast<const char*>(data), size),
                                   fitbase::core::kFullVertexCount, "fuzz input");
  return 0;
}
