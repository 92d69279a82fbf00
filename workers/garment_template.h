#ifndef FITBASE_WORKERS_GARMENT_TEMPLATE_H_
#define FITBASE_WORKERS_GARMENT_TEMPLATE_H_

#include "absl/status/statusor.h"
#include "core/mesh.h"
#include "workers/cloth_solver.h"

namespace fitbase::workers {

// Search radius of the push-outs that start and end a fit: a garment placed by its binding or
// by a retailer may start centimeters inside the body where the mean avatar is fuller than the
// body it was modelled on, and a vertex the drape let slip through stays within this.
inline constexpr double kTemplatePushSearch = 0.08;

// Turns a garment placed on the mean avatar into its template: every vertex pushed outside
// the body by the collision offset, then relaxed under gravity for `relax_steps` towards the
// edge lengths of `rest` (the garment's own shape). placed, rest: V x 3 (m); body: the mean
// avatar's body (13,380 x 3, m) with its triangles. Vertex order and faces are unchanged.
absl::StatusOr<core::Positions> FitTemplateToBody(const core::Positions& placed,
                                                  const core::Positions& rest,
                                                  const core::PolygonFaces& faces,
                                                  const core::Positions& body,
                                                  const core::Triangles& body_triangles,
                                                  const ClothSettings& settings = {},
                                                  int relax_steps = 10);

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_GARMENT_TEMPLATE_H_
