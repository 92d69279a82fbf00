// A stored clothing basis (`.fbc`, the store's clothing basis versions): the v1::ClothingBasis
// message parsed, then what `fitbase fit` and the fit service decode of it
// (proto::ClothingFitterFromProto, proto::GarmentMeshFromClothingBasis) and one fit with its
// clean-up, which trusts the validation; then the same fit to a mesh given with the weights
// (FitToBody, whose gather checks the basis's body vertices against the mesh).
#include <cstdint>
#include <vector>

#include "body/body_model.h"
#include "clothing/clothing_fitter.h"
#include "fitbase/v1/clothing_basis.pb.h"
#include "proto/clothing_basis_codec.h"

namespace {

// A fit takes one weight per component, which the caller sends: the fit service's 4 MB request
// limit keeps them far below this, and a weight vector of a forged count is the caller's
// allocation, not the parser's.
constexpr int kMaxFitComponents = 1 << 16;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fitbase::v1::ClothingBasis message;
  if (!message.ParseFromArray(data, static_cast<int>(size))) return 0;
  (void)fitbase::proto::GarmentMeshFromClothingBasis(message);
  auto fitter = fitbase::proto::ClothingFitterFromProto(message);
  if (!fitter.ok() || fitter->component_count() > kMaxFitComponents) return 0;
  const Eigen::VectorXf weights = Eigen::VectorXf::Constant(fitter->component_count(), 0.01f);
  fitbase::clothing::FitScratch scratch;
  Eigen::VectorXf positions;
  (void)fitter->Fit(weights, /*cleanup=*/true, scratch, positions);
  // An hm08-sized mesh 1 mm above the origin: any basis vertex past it must be refused.
  std::vector<float> mesh(3 * static_cast<size_t>(fitbase::body::kBodyVertexCount));
  for (size_t i = 1; i < mesh.size(); i += 3) mesh[i] = 0.001f;
  (void)fitter->FitToBody(weights, mesh, /*cleanup=*/true, scratch, positions);
  return 0;
}
