#ifndef FITBASE_PROTO_DRACO_CODEC_H_
#define FITBASE_PROTO_DRACO_CODEC_H_

#include <cstdint>
#include <span>
#include <vector>

#include "absl/status/statusor.h"
#include "fitbase/v1/mesh.pb.h"

namespace fitbase::proto {

// Every linear model relates vertex i of one mesh to vertex i of another, so positions keep
// the vertex order on the wire. Of Draco's encodings only the sequential point cloud does: the
// kd-tree point-cloud and Edgebreaker mesh encoders reorder points, and the sequential mesh
// encoder predicts no better while adding the faces (measured: docs/avatar-format.md).
struct DracoSettings {
  // Per axis, over the bounding box's longest side L: any coordinate moves by at most
  // L / (2^bits - 1) / 2, 0.41 mm on a 1.67 m body at 11 bits. Sequential encoding predicts
  // each vertex from the one before, so the size depends on how far apart consecutive
  // vertices lie. At 11 bits: 5.1x below raw float32 for the hm08 body, 4.1-4.4x for garments
  // whose consecutive vertices are 2-3 cm apart, but only 3.0-3.4x for the MakeHuman garments
  // stored coarse to fine (consecutive vertices 5-30 cm apart). 11 is the finest setting that
  // keeps the coherent ones >= 4x. Range 1..30.
  int quantization_bits = 11;
};

// xyz: V x 3 row-major (3 floats per vertex), float32 meters; xyz.size() must be a multiple
// of 3. Exact.
v1::EncodedPositions EncodeRawPositions(std::span<const float> xyz);

// xyz as for EncodeRawPositions, with at least one vertex, all finite. The message states the
// quantization and a bound on any coordinate's error (max_error_m). INVALID_ARGUMENT for bad
// settings or input.
absl::StatusOr<v1::EncodedPositions> EncodeDracoPositions(std::span<const float> xyz,
                                                          const DracoSettings& settings = {});

// The positions as V x 3 row-major floats, meters, V = expected_vertex_count, in vertex order.
// INVALID_ARGUMENT naming the problem: another vertex count, no encoding, a raw value count
// other than 3V, a non-finite value, or a Draco payload that does not decode, is not a
// sequential point cloud (which would have reordered the points), or does not hold exactly V
// points with a 3-component position attribute. Untrusted payloads are safe to decode: a
// payload claiming another point count is refused before Draco allocates for it.
absl::StatusOr<std::vector<float>> DecodePositions(const v1::EncodedPositions& positions,
                                                   int64_t expected_vertex_count);

}  // namespace fitbase::proto

#endif  // FITBASE_PROTO_DRACO_CODEC_H_
