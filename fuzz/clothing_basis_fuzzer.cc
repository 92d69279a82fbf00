// A stored clothing basis (`.fbc`, the store's clothing basis versions): the v1::ClothingBasis
// message parsed, then what `fitbase fit` and the fit service decode of it
// (proto::ClothingFitterFromProto, proto::GarmentMeshFromClothingBasis) and one fit with its
// clean-up, which trusts the validation; then the same fit to a mesh given with the weights
// (FitToBody, whose gather checks the basis's body vertices against the mesh, and whose deep
// pushes search it).
#include <cmath>
#include <cstdint>
#include <vector>

#include "body/body_model.h"
#include "clothing/clothing_fitter.h"
#include "core/mesh.h"
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
  if (!fitter.ok() || fitter->model().component_count > kMaxFitComponents) return 0;
  const Eigen::VectorXf weights = Eigen::VectorXf::Constant(fitter->model().component_count, 0.01f);
  fitbase::clothing::FitScratch scratch;
  Eigen::VectorXf positions;
  (void)fitter->Fit(weights, /*cleanup=*/true, scratch, positions);
  // An hm08-sized mesh, a strip of triangles over a spiral of half a metre: any basis vertex
  // past it must be refused, and a deep push meets a surface to check against.
  const int64_t vertex_count = fitbase::body::kBodyVertexCount;
  std::vector<float> mesh(3 * static_cast<size_t>(vertex_count));
  for (int64_t i = 0; i < vertex_count; ++i) {
    mesh[3 * i] = 0.5f * std::cos(0.1f * static_cast<float>(i));
    mesh[3 * i + 1] = 1e-4f * static_cast<float>(i);
    mesh[3 * i + 2] = 0.5f * std::sin(0.1f * static_cast<float>(i));
  }
  fitbase::core::Triangles strip(vertex_count - 2, 3);
  for (int64_t t = 0; t < strip.rows(); ++t) {
    strip.row(t) << static_cast<int32_t>(t), static_cast<int32_t>(t + 1),
        static_cast<int32_t>(t + 2);
  }
  (void)fitter->FitToBody(weights, {.positions = mesh, .triangles = &strip}, /*cleanup=*/true,
                          scratch, positions);
  return 0;
}
