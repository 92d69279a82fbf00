#ifndef FITBASE_SERVICES_FIT_FIT_CATALOG_H_
#define FITBASE_SERVICES_FIT_FIT_CATALOG_H_

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "absl/time/time.h"
#include "clothing/clothing_fitter.h"
#include "fitbase/v1/fit_service.pb.h"
#include "pipeline/avatar_projection.h"
#include "pipeline/size_advisor.h"
#include "services/fit/byte_lru_cache.h"
#include "services/rpc/clock.h"
#include "storage/asset_store.h"

namespace fitbase::fit {

// A clothing basis ready to fit: the published version it was loaded from.
struct ServedClothing {
  clothing::ClothingFitter fitter;
  uint64_t version = 0;
  std::string content_id;
  // Per component, the largest |weight| of the example drapes the basis was built from (m):
  // a customer far beyond it is a fit by extrapolation.
  Eigen::VectorXd example_reach;
};

// What the fit service needs of a garment record (not its template or mean avatar).
struct ServedGarment {
  std::string avatar_basis_id;
  v1::GarmentTopology topology;
  // For size advice; null, with the reason in advice_error, for a record it cannot use.
  std::shared_ptr<const pipeline::AdviceGarment> advice;
  absl::Status advice_error;
};

struct FitCatalogOptions {
  size_t max_bytes = size_t{1} << 30;  // Budget of every cache together, by value size.
  // How stale a cached "current" may be: pointers are re-read from the store this often, so a
  // newly published version serves within this time, without a restart.
  absl::Duration refresh = absl::Seconds(1);
  const rpc::Clock* clock = nullptr;  // Null: the real clock.
};

// The fit service's read side of the asset store: garments, the current clothing basis of
// each (garment, size, avatar basis, method) and the current avatar basis of each
// (tenant, population), parsed once and kept in LRU caches bounded by bytes. Garments and
// avatar bases are immutable; current pointers are re-checked every `refresh` through the
// store's index (no blob reads). Thread-safe.
class FitCatalog {
 public:
  FitCatalog(const storage::AssetStore* store, const FitCatalogOptions& options);

  // NOT_FOUND for a garment of another tenant.
  absl::StatusOr<std::shared_ptr<const ServedGarment>> Garment(absl::string_view tenant,
                                                              absl::string_view garment_id);
  absl::StatusOr<std::shared_ptr<const ServedClothing>> Clothing(
      const storage::ClothingBasisKey& key);
  absl::StatusOr<std::shared_ptr<const pipeline::LoadedAvatarBasis>> CurrentAvatarBasis(
      absl::string_view tenant, absl::string_view population);
  absl::StatusOr<std::vector<std::string>> ListGarmentIds(absl::string_view tenant) const {
    return store_->ListGarmentIds(tenant);
  }
  // Population name to current avatar basis id, read from the store each call (a listing is
  // rare: once per page load).
  absl::StatusOr<std::map<std::string, std::string>> CurrentAvatarBases(
      absl::string_view tenant) const {
    return store_->ListCurrentAvatarBases(tenant);
  }
  // By id, whichever tenant published it: callers reach an id only through their own
  // tenant's garments or pointers.
  absl::StatusOr<std::shared_ptr<const pipeline::LoadedAvatarBasis>> AvatarBasis(
      absl::string_view avatar_basis_id);

 private:
  absl::Time Now() const { return clock_->Now(); }

  const storage::AssetStore* store_;
  const FitCatalogOptions options_;
  const rpc::RealClock real_clock_;
  const rpc::Clock* clock_;
  ByteLruCache<ServedGarment> garments_;
  ByteLruCache<ServedClothing> clothing_;
  ByteLruCache<pipeline::LoadedAvatarBasis> avatar_bases_;
  // Current avatar basis id per (tenant, population).
  ByteLruCache<std::string> avatar_pointers_;
};

}  // namespace fitbase::fit

#endif  // FITBASE_SERVICES_FIT_FIT_CATALOG_H_
