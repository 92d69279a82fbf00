#ifndef FITBASE_PIPELINE_SIZE_ADVISOR_H_
#define FITBASE_PIPELINE_SIZE_ADVISOR_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "body/body_measurements.h"
#include "clothing/garment_measure.h"
#include "clothing/size_advice.h"
#include "core/mesh.h"
#include "core/triangle_bvh.h"
#include "fitbase/v1/fit_service.pb.h"
#include "fitbase/v1/garment.pb.h"

namespace fitbase::pipeline {

// What size advice needs of a garment, prepared once per garment record: its triangles, each
// size's rest edge lengths, the vertices that make its sleeves and legs, and the ease of its
// lengths as designed (the template on the mean body).
struct AdviceGarment {
  clothing::GarmentType type = clothing::GarmentType::kShirt;
  core::Triangles triangles;
  std::vector<std::string> size_names;                // As stored (grading order).
  std::vector<clothing::TriangleEdgeLengths> rest;        // Per size.
  std::vector<int32_t> sleeve_vertices;               // The left sleeve's.
  std::vector<int32_t> leg_vertices;                  // The left trouser leg's.
  std::vector<int32_t> torso_vertices;
  // Design ease (cm) of garment_length and sleeve_length; NaN when the garment has none.
  double design_length_cm = 0;
  double design_sleeve_cm = 0;
};

// The garment type is the record's `garment_type` ("shirt" when empty). INVALID_ARGUMENT for
// a record that does not hold together (counts, sizes, an unknown type).
absl::StatusOr<AdviceGarment> PrepareAdviceGarment(const v1::Garment& garment);

// A body measured for advice: positions 13,380 x 3 (m) with its topology's triangles.
struct AdviceBody {
  core::Positions positions;
  core::Triangles triangles;
  body::BodyMeasurements measurements;
  std::array<std::optional<body::GirthPlace>, body::kMeasurementCount> places;
  // Per torso girth, the body's section there split into the torso's loop and the rest (the
  // arms beside it), world points: a garment's section point counts for the torso when the
  // torso is its nearest part of the body, so that sleeves beside the chest are left out.
  struct TorsoSection {
    std::vector<Eigen::Vector3d> torso;
    std::vector<Eigen::Vector3d> others;
  };
  std::array<TorsoSection, body::kMeasurementCount> torso_sections;
  core::TriangleBvh bvh;
};
absl::StatusOr<AdviceBody> MeasureAdviceBody(core::Positions positions, core::Triangles triangles);

// One size fitted to the body: its regions (judged) and per-vertex fit map. fitted: V x 3 (m)
// in the garment's vertex order.
struct SizeJudgement {
  std::vector<clothing::RegionFitValue> regions;
  Eigen::VectorXf ease_mm;
  Eigen::VectorXf stretch_pct;
};
absl::StatusOr<SizeJudgement> JudgeSize(const AdviceGarment& garment, int size,
                                        const AdviceBody& body, const core::Positions& fitted);

// The whole advice over judged sizes (indices into garment.size_names, smallest first), with
// the fit maps when `with_maps`.
v1::SizeAdvice AssembleAdvice(const AdviceGarment& garment, const std::vector<int>& sizes,
                              const std::vector<SizeJudgement>& judged, bool with_maps);

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_SIZE_ADVISOR_H_
