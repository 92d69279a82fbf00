#ifndef FITBASE_WORKERS_GARMENT_DRAPE_H_
#define FITBASE_WORKERS_GARMENT_DRAPE_H_

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "core/mesh.h"
#include "fitbase/v1/garment.pb.h"
#include "workers/drape.h"

namespace fitbase::workers {

// A garment fitted to one body, in the template's vertex order, with its fit report.
struct GarmentFit {
  core::Positions positions;  // V x 3, m.
  v1::DrapeReport report;
};

// The size named `size`, or NOT_FOUND listing the garment's sizes.
absl::StatusOr<const v1::GarmentSize*> FindGarmentSize(const v1::Garment& garment,
                                                       absl::string_view size);

// The physics drape of `garment` in `size` on `target_body` (the 13,380 x 3 body avatar,
// m). Errors: unknown size (the message lists the garment's sizes), a body of another vertex
// count, non-finite positions, an inconsistent garment message.
absl::StatusOr<GarmentFit> DrapeGarment(const v1::Garment& garment, absl::string_view size,
                                        const core::Positions& target_body,
                                        const ClothSettings& settings = {},
                                        const DrapeSchedule& schedule = {});

// The `geometric` baseline: MakeHuman's .mhclo binding applied to the target body, whose
// helper geometry (which the binding refers to) follows the body surface nearest it on the
// mean avatar. The same for every size; measured against the size's rest lengths.
// FAILED_PRECONDITION for garments imported without a binding.
absl::StatusOr<GarmentFit> GeometricFit(const v1::Garment& garment, absl::string_view size,
                                        const core::Positions& target_body);

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_GARMENT_DRAPE_H_
