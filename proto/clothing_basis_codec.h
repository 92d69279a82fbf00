#ifndef FITBASE_PROTO_CLOTHING_BASIS_CODEC_H_
#define FITBASE_PROTO_CLOTHING_BASIS_CODEC_H_

#include "absl/status/statusor.h"
#include "clothing/body_correspondence.h"
#include "clothing/clothing_fitter.h"
#include "clothing/clothing_model.h"
#include "core/garment_obj.h"
#include "fitbase/v1/clothing_basis.pb.h"

namespace fitbase::proto {

// Writes the model's method, sizes, mean and terms into `message` (other fields untouched).
void ClothingModelToProto(const clothing::ClothingModel& model, v1::ClothingBasis* message);

void BodyCorrespondenceToProto(const clothing::BodyCorrespondence& correspondence,
                               v1::BodyCorrespondence* message);

// The model of a stored clothing basis, validated (sizes, term indices, finite values).
absl::StatusOr<clothing::ClothingModel> ClothingModelFromProto(const v1::ClothingBasis& message);

// Its collision clean-up data, validated against the basis's vertex and component counts.
absl::StatusOr<clothing::BodyCorrespondence> BodyCorrespondenceFromProto(
    const v1::ClothingBasis& message);

// The fitter of a stored clothing basis: its model and body correspondence, validated.
absl::StatusOr<clothing::ClothingFitter> ClothingFitterFromProto(const v1::ClothingBasis& message);

// The garment's mesh as the basis stores it (faces and texture coordinates), positioned at
// the clothing mean; callers put a fit's positions in its place.
absl::StatusOr<core::GarmentMesh> GarmentMeshFromClothingBasis(const v1::ClothingBasis& message);

}  // namespace fitbase::proto

#endif  // FITBASE_PROTO_CLOTHING_BASIS_CODEC_H_
