#ifndef FITBASE_WORKERS_CLOTH_MODEL_H_
#define FITBASE_WORKERS_CLOTH_MODEL_H_

#include <array>
#include <cstdint>
#include <vector>

#include "Eigen/Core"
#include "absl/status/statusor.h"
#include "core/mesh.h"

namespace fitbase::workers {

// The constraint topology of a garment for the cloth solver, derived once from its faces.
// Vertex order is the garment's; constraints are stored in a fixed order so a solve visits
// them the same way every time.
struct ClothModel {
  core::Triangles triangles;  // Fan triangulation of the faces.
  // Stretch and shear: every distinct triangle edge (quad diagonals shear), i < j.
  std::vector<std::array<int32_t, 2>> edges;
  // Bending: for each edge shared by exactly two triangles, {edge end, edge end, the first
  // triangle's third vertex, the second triangle's third vertex} (see core::HingeAngle).
  std::vector<std::array<int32_t, 4>> hinges;
  // Per vertex: 1 / mass (kg^-1); 0 for vertices no face uses (they never move).
  Eigen::VectorXd inverse_masses;
  // The garment's top openings (waistband, collar, shoe opening): per connected piece, the
  // boundary loop highest on the template. These keep their height on the body, as a belt or
  // elastic would, so a garment stays where it is worn instead of sliding off a smaller body.
  std::vector<int32_t> anchor_vertices;
};

// positions: the template, V x 3 (m); faces as given (polygons). areal_density: kg/m^2.
// Errors: a face index out of range, a degenerate model (no triangles).
absl::StatusOr<ClothModel> BuildClothModel(const core::Positions& positions,
                                           const core::PolygonFaces& faces,
                                           double areal_density);

// Current bending angles of `hinges` for `positions` (rad; 0 for a degenerate hinge).
Eigen::VectorXd HingeAngles(const core::Positions& positions,
                            const std::vector<std::array<int32_t, 4>>& hinges);

// Current lengths of `pairs` for `positions`.
Eigen::VectorXd PairLengths(const core::Positions& positions,
                            const std::vector<std::array<int32_t, 2>>& pairs);

// Areas of `model.triangles` (T) whose sides have the rest lengths `edge_rest` (per
// model.edges, m), by Heron's formula, m^2: a sized garment's triangles at rest. 0 for a
// triangle whose rest lengths do not close.
Eigen::VectorXd TriangleRestAreas(const ClothModel& model, const Eigen::VectorXd& edge_rest);

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_CLOTH_MODEL_H_
