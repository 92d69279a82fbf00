// A stored drape result (`.fbd` in a drape cache, the store's drape results): the
// v1::DrapeResult message parsed, then workers::DrapeResultPositions, the check a clothing
// basis assembly runs on each, against the vertex count its garment would have (here the
// count the positions claim, rounded up, so that both matching and mismatching counts occur).
#include <cstdint>

#include "fitbase/v1/clothing_basis.pb.h"
#include "workers/drape_task.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fitbase::v1::DrapeResult result;
  if (!result.ParseFromArray(data, static_cast<int>(size))) return 0;
  (void)fitbase::workers::DrapeResultPositions(result, (result.positions_size() + 2) / 3);
  return 0;
}
