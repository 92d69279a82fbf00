// A MakeHuman `.target` morph target: body::ParseTarget against the full hm08 mesh, as the
// body model loads them.
#include <cstdint>

#include "absl/strings/string_view.h"
#include "body/body_model.h"
#include "body/target_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)fitbase::body::ParseTarget(absl::string_view(reinterpret_cast<const char*>(data), size),
                                   fitbase::body::kFullVertexCount, "fuzz input");
  return 0;
}
