// A drape task as a worker leases it from the coordinator (v1::DrapeTaskSpec: garment, size,
// body, settings and its content key): parsed, then workers::DrapeTaskFromSpec, which
// validates the settings and recomputes the key. The drape is not run: it is seconds per input.
#include <cstdint>

#include "fitbase/v1/build.pb.h"
#include "workers/drape_task_spec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fitbase::v1::DrapeTaskSpec spec;
  if (spec.ParseFromArray(data, static_cast<int>(size))) {
    (void)fitbase::workers::DrapeTaskFromSpec(spec);
  }
  return 0;
}
