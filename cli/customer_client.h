#ifndef FITBASE_CLI_CUSTOMER_CLIENT_H_
#define FITBASE_CLI_CUSTOMER_CLIENT_H_

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "cli/remote_flags.h"
#include "fitbase/v1/fit_service.grpc.pb.h"
#include "services/rpc/channel.h"
#include "services/rpc/grpc_status.h"

namespace fitbase::cli {

// Draco-encoded positions (3V floats, in the topology's wire order) in vertex order;
// INVALID_ARGUMENT when the topology's wire order is not a permutation of V vertices.
absl::StatusOr<std::vector<float>> FromWireOrder(const v1::GarmentTopology& topology,
                                                 const std::vector<float>& wire);

// A shop's client of the fit service: fits garments and writes them as OBJ files, fetching
// each garment's topology once (fits carry positions only).
class CustomerClient {
 public:
  explicit CustomerClient(const RemoteFlags& remote);

  // body: the customer's own mesh to fit to (FitGarmentRequest.body), or null for the body of
  // the weights.
  absl::StatusOr<v1::FittedGarment> Fit(const v1::AvatarWeights& weights,
                                        const std::string& garment_id, const std::string& size,
                                        const std::string& method, bool raw,
                                        const v1::Avatar* body);
  absl::StatusOr<v1::FitOutfitResponse> Outfit(const v1::FitOutfitRequest& request);
  absl::StatusOr<v1::GarmentTopology> Topology(const std::string& garment_id);
  // The fitted positions (3V float32, m), decoded and checked against the topology.
  absl::StatusOr<std::vector<float>> Positions(const v1::FittedGarment& fitted);
  // The fitted garment with its faces and texture coordinates.
  absl::Status WriteObj(const v1::FittedGarment& fitted, const std::filesystem::path& path);

 private:
  RemoteFlags remote_;
  std::unique_ptr<v1::FitService::Stub> stub_;
  std::map<std::string, v1::GarmentTopology> topologies_;
};

}  // namespace fitbase::cli

#endif  // FITBASE_CLI_CUSTOMER_CLIENT_H_
