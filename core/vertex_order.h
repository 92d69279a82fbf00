#ifndef FITBASE_CORE_VERTEX_ORDER_H_
#define FITBASE_CORE_VERTEX_ORDER_H_

#include <cstdint>
#include <vector>

#include "core/mesh.h"

namespace fitbase::core {

// The vertices in Z-order (Morton order) of their positions quantized to 2^10 cells per axis
// over the bounding box, ties by index: consecutive vertices are spatial neighbours, which is
// what sequential coders (Draco's sequential point cloud predicts each point from the one
// before) need. positions: V x 3, any unit. Returns V distinct indices (order[i] = the vertex
// at wire position i). Deterministic: depends on the positions only.
std::vector<uint32_t> SpatialOrder(const Positions& positions);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_VERTEX_ORDER_H_
