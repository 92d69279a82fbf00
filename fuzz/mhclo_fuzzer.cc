// A garment's `.mhclo` binding as a retailer uploads it: core::ParseMhclo against the full hm08
// mesh, then core::ApplyMhclo, which trusts the parser to have checked every index.
#include <cstdint>

#include "absl/strings/string_view.h"
#include "body/body_model.h"
#include "core/mhclo_binding.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using fitbase::body::kFullVertexCount;
  static const fitbase::core::Positions reference =
      fitbase::core::Positions::Random(kFullVertexCount, 3);
  auto binding = fitbase::core::ParseMhclo(
      absl::string_view(reinterpret_cast<const char*>(data), size), kFullVertexCount,
      "fuzz input");
  if (binding.ok()) (void)fitbase::core::ApplyMhclo(*binding, reference);
  return 0;
}
