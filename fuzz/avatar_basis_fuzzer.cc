// A stored avatar basis (`.fbb`, the store's avatar basis records, PublishAvatarBasis uploads):
// the v1::AvatarBasis message parsed, then what every reader decodes of it:
// proto::PcaBasisFromProto (validated) and its mean mesh (proto::MeshFromProto), and a
// projection and reconstruction on the decoded basis.
#include <cstdint>

#include "core/pca_basis.h"
#include "fitbase/v1/avatar_basis.pb.h"
#include "proto/avatar_basis_codec.h"
#include "proto/mesh_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fitbase::v1::AvatarBasis message;
  if (!message.ParseFromArray(data, static_cast<int>(size))) return 0;
  (void)fitbase::proto::MeshFromProto(message.mean());
  auto basis = fitbase::proto::PcaBasisFromProto(message);
  if (!basis.ok()) return 0;
  const Eigen::VectorXd weights = fitbase::core::ProjectOntoBasis(*basis, basis->mean);
  (void)fitbase::core::ReconstructFromWeights(*basis, weights);
  return 0;
}
