#include "cli/customer_client.h"

#include "absl/strings/str_cat.h"
#include "core/garment_obj.h"
#include "core/status_macros.h"
#include "proto/draco_codec.h"
#include "proto/mesh_codec.h"

namespace fitbase::cli {

absl::StatusOr<std::vector<float>> FromWireOrder(const v1::GarmentTopology& topology,
                                                 const std::vector<float>& wire) {
  const auto& order = topology.wire_order();
  if (static_cast<size_t>(order.size()) * 3 != wire.size()) {
    return absl::InvalidArgumentError(absl::StrCat("garment ", topology.garment_id(), ": ",
                                                   order.size(), " wire positions for ",
                                                   wire.size() / 3, " vertices"));
  }
  std::vector<float> xyz(wire.size());
  std::vector<bool> seen(order.size(), false);
  for (int i = 0; i < order.size(); ++i) {
    if (order[i] >= static_cast<uint32_t>(order.size()) || seen[order[i]]) {
      return absl::InvalidArgumentError(
          absl::StrCat("garment ", topology.garment_id(), ": wire_order is not a permutation"));
    }
    seen[order[i]] = true;
    for (int c = 0; c < 3; ++c) xyz[3 * order[i] + c] = wire[3 * i + c];
  }
  return xyz;
}

CustomerClient::CustomerClient(const RemoteFlags& remote)
    : remote_(remote), stub_(v1::FitService::NewStub(rpc::OpenChannel(remote.address))) {}

absl::StatusOr<v1::FittedGarment> CustomerClient::Fit(const v1::AvatarWeights& weights,
                                                      const std::string& garment_id,
                                                      const std::string& size,
                                                      const std::string& method, bool raw,
                                                      const v1::Avatar* body) {
  v1::FitGarmentRequest request;
  *request.mutable_weights() = weights;
  if (body != nullptr) *request.mutable_body() = *body;
  request.set_garment_id(garment_id);
  request.set_size(size);
  request.set_method(method);
  request.set_encoding(raw ? v1::POSITIONS_ENCODING_RAW : v1::POSITIONS_ENCODING_DRACO);
  request.set_with_metrics(true);
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> context,
                   NewCallContext(remote_, absl::Seconds(remote_.timeout_seconds)));
  v1::FittedGarment fitted;
  RETURN_IF_ERROR(rpc::FromGrpcStatus(stub_->FitGarment(context.get(), request, &fitted)));
  return fitted;
}

absl::StatusOr<v1::FitOutfitResponse> CustomerClient::Outfit(
    const v1::FitOutfitRequest& request) {
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> context,
                   NewCallContext(remote_, absl::Seconds(remote_.timeout_seconds)));
  v1::FitOutfitResponse response;
  RETURN_IF_ERROR(rpc::FromGrpcStatus(stub_->FitOutfit(context.get(), request, &response)));
  return response;
}

absl::StatusOr<v1::GarmentTopology> CustomerClient::Topology(const std::string& garment_id) {
  if (auto it = topologies_.find(garment_id); it != topologies_.end()) return it->second;
  v1::GetGarmentTopologyRequest request;
  request.set_garment_id(garment_id);
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> context,
                   NewCallContext(remote_, absl::Seconds(remote_.timeout_seconds)));
  v1::GarmentTopology topology;
  RETURN_IF_ERROR(
      rpc::FromGrpcStatus(stub_->GetGarmentTopology(context.get(), request, &topology)));
  return topologies_[garment_id] = std::move(topology);
}

absl::StatusOr<std::vector<float>> CustomerClient::Positions(const v1::FittedGarment& fitted) {
  ASSIGN_OR_RETURN(v1::GarmentTopology topology, Topology(fitted.garment_id()));
  ASSIGN_OR_RETURN(std::vector<float> decoded,
                   proto::DecodePositions(fitted.positions(), topology.vertex_count()));
  if (!fitted.positions().has_draco()) return decoded;
  return FromWireOrder(topology, decoded);
}

absl::Status CustomerClient::WriteObj(const v1::FittedGarment& fitted,
                                      const std::filesystem::path& path) {
  ASSIGN_OR_RETURN(v1::GarmentTopology topology, Topology(fitted.garment_id()));
  ASSIGN_OR_RETURN(std::vector<float> positions, Positions(fitted));
  v1::Mesh mesh = topology.faces();
  mesh.mutable_positions()->Assign(positions.begin(), positions.end());
  core::GarmentMesh garment;
  ASSIGN_OR_RETURN(garment.mesh, proto::MeshFromProto(mesh));
  garment.texcoords.resize(topology.texcoords_size() / 2, 2);
  for (int i = 0; i < topology.texcoords_size(); ++i) {
    garment.texcoords.data()[i] = topology.texcoords(i);
  }
  garment.face_texcoord_indices.assign(topology.face_texcoord_indices().begin(),
                                       topology.face_texcoord_indices().end());
  return core::WriteGarmentObj(path, garment);
}

}  // namespace fitbase::cli
