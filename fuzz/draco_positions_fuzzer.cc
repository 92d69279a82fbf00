// A Draco position payload (an avatar's, or a fitted garment's as the customer client decodes
// it) straight into proto::DecodePositions, without a message around it so that mutations hit
// the bitstream. Input: the expected vertex count (2 bytes, little-endian, plus one), then the
// payload (fuzz/draco_seeds.cc writes seeds).
#include <cstdint>
#include <string>

#include "fitbase/v1/mesh.pb.h"
#include "proto/draco_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const int64_t vertex_count = 1 + (data[0] | (data[1] << 8));
  fitbase::v1::EncodedPositions positions;
  positions.set_vertex_count(static_cast<uint32_t>(vertex_count));
  positions.mutable_draco()->set_data(
      std::string(reinterpret_cast<const char*>(data) + 2, size - 2));
  (void)fitbase::proto::DecodePositions(positions, vertex_count);
  return 0;
}
