// A stored build record (v1::Build, as the coordinator's store keeps it): parsed, then
// re-planned with build::PlanBuild exactly as a restarted coordinator's Recover does, against a
// real asset store holding one tenant's garment and avatar basis. The store is a temporary
// RocksDB made at start-up from $FITBASE_FUZZ_CATALOGUE/{g.fbg,b.fbb} (tests/small_catalogue.sh
// makes them; fuzz/make_corpus.sh sets it); without it every plan stops at NOT_FOUND.
#include <stdlib.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "core/file_util.h"
#include "fitbase/v1/avatar_basis.pb.h"
#include "fitbase/v1/build.pb.h"
#include "fitbase/v1/garment.pb.h"
#include "services/build/build_plan.h"
#include "storage/asset_store.h"

namespace fitbase {
namespace {

class FuzzStore {
 public:
  FuzzStore() {
    std::string pattern = (std::filesystem::temp_directory_path() / "fitbase-fuzz-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) std::abort();
    dir_ = pattern;
    auto store = storage::AssetStore::Open(dir_ / "db", {});
    if (!store.ok()) {
      std::cerr << store.status() << "\n";
      std::abort();
    }
    store_ = *std::move(store);
    const char* catalogue = std::getenv("FITBASE_FUZZ_CATALOGUE");
    if (catalogue == nullptr) return;
    auto garment_bytes = core::ReadFileToString(std::filesystem::path(catalogue) / "g.fbg");
    auto basis_bytes = core::ReadFileToString(std::filesystem::path(catalogue) / "b.fbb");
    v1::Garment garment;
    if (!garment_bytes.ok() || !basis_bytes.ok() || !garment.ParseFromString(*garment_bytes) ||
        !store_->PutGarment("fuzz", garment.id(), *garment_bytes).ok() ||
        !store_->PutAvatarBasis(garment.avatar_basis_id(), *basis_bytes).ok()) {
      std::cerr << "cannot load the catalogue in " << catalogue << "\n";
      std::abort();
    }
  }
  ~FuzzStore() {
    store_.reset();
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  const storage::AssetStore& store() const { return *store_; }

 private:
  std::filesystem::path dir_;
  std::unique_ptr<storage::AssetStore> store_;
};

}  // namespace
}  // namespace fitbase

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const fitbase::FuzzStore store;
  fitbase::v1::Build build;
  if (build.ParseFromArray(data, static_cast<int>(size))) {
    (void)fitbase::build::PlanBuild(store.store(), build.tenant(), build.request());
  }
  return 0;
}
