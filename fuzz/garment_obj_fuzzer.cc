// A garment OBJ as a retailer uploads it: core::ParseGarmentObj, fitbase's own OBJ parser.
#include <cstdint>

#include "absl/strings/string_view.h"
#include "core/garment_obj.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)fitbase::core::ParseGarmentObj(
      absl::string_view(reinterpret_cast<const char*>(data), size), "fuzz input");
  return 0;
}
