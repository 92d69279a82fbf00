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

// What a template is fitted with: ClothSettings's defaults, but collars held as softly as
// before the supports (kUnsupportedAnchorStiffness). The relaxation starts from the binding's
// placement, not from a drape, and a collar held at 200 N/m there left female_casualsuit02's
// template so that its drapes jumped between nearby bodies (p99 of the second difference at
// 0.1 sigma 12.6 mm, against 1.9 mm with the collar held softly; male_worksuit01 3.8 against
// 2.6; fitbase_drape_bench --smoothness-only on fresh imports).
ClothSettings TemplateFitSettings();

// Turns a garment placed on the mean avatar into its template: every vertex pushed outside
// the body by the collision offset, then relaxed under gravity for `relax_steps` towards the
// edge lengths of `rest` (the garment's own shape). placed, rest: V x 3 (m); body: the mean
// avatar's body (13,380 x 3, m) with its triangles. Vertex order and faces are unchanged.
absl::StatusOr<core::Positions> FitTemplateToBody(const core::Positions& placed,
                                                  const core::Positions& rest,
                                                  const core::PolygonFaces& faces,
                                                  const core::Positions& body,
                                                  const core::Triangles& body_triangles,
                                                  const ClothSettings& settings =
                                                      TemplateFitSettings(),
                                                  int relax_steps = 10);

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_GARMENT_TEMPLATE_H_
