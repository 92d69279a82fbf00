#include "workers/garment_template.h"

#include "body/body_model.h"
#include "core/status_macros.h"
#include "core/triangle_bvh.h"
#include "workers/cloth_model.h"

namespace fitbase::workers {

ClothSettings TemplateFitSettings() {
  ClothSettings settings;
  settings.anchor_stiffness = kUnsupportedAnchorStiffness;
  return settings;
}

absl::StatusOr<core::Positions> FitTemplateToBody(const core::Positions& placed,
                                                  const core::Positions& rest,
                                                  const core::PolygonFaces& faces,
                                                  const core::Positions& body,
                                                  const core::Triangles& body_triangles,
                                                  const ClothSettings& settings,
                                                  int relax_steps) {
  if (!placed.allFinite() || !rest.allFinite()) {
    return absl::InvalidArgumentError("garment placement or rest shape is not finite");
  }
  if (rest.rows() != placed.rows()) {
    return absl::InvalidArgumentError("garment rest shape and placement differ in vertex count");
  }
  ASSIGN_OR_RETURN(ClothModel model, BuildClothModel(placed, faces, settings.areal_density));
  ASSIGN_OR_RETURN(core::TriangleBvh bvh, core::TriangleBvh::Build(body, body_triangles));
  // The relaxation runs with friction and no skin ties, so trousers need their waistband to
  // stay up; a body without the avatar's landmarks (a test shape) has none.
  Supports supports;
  if (body.rows() == body::kBodyVertexCount) {
    ASSIGN_OR_RETURN(supports, FindSupports(model, placed, body));
  }
  ClothSolver pusher(model, placed, PairLengths(placed, model.edges),
                     HingeAngles(placed, model.hinges), supports, bvh, settings);
  pusher.ResolveCollisions(bvh, kTemplatePushSearch, settings.collision_offset);
  ClothSolver solver(model, pusher.positions(), PairLengths(rest, model.edges),
                     HingeAngles(rest, model.hinges), supports, bvh, settings);
  for (int step = 0; step < relax_steps; ++step) solver.Step(bvh);
  solver.ResolveCollisions(bvh, kTemplatePushSearch, settings.collision_offset);
  return solver.positions();
}

}  // namespace fitbase::workers
