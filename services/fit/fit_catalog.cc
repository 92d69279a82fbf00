#include "services/fit/fit_catalog.h"

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "core/vertex_order.h"
#include "proto/avatar_basis_codec.h"
#include "proto/clothing_basis_codec.h"
#include "proto/mesh_codec.h"

namespace fitbase::fit {
namespace {

std::string CacheKey(std::initializer_list<absl::string_view> ids) {
  std::string key;
  for (absl::string_view id : ids) absl::StrAppend(&key, id, std::string(1, '\0'));
  return key;
}

}  // namespace

FitCatalog::FitCatalog(const storage::AssetStore* store, const FitCatalogOptions& options)
    : store_(store),
      options_(options),
      clock_(options.clock ? options.clock : &real_clock_),
      garments_(options.max_bytes / 8),
      clothing_(options.max_bytes / 2),
      avatar_bases_(options.max_bytes / 4),
      avatar_pointers_(size_t{1} << 20) {}

absl::StatusOr<std::shared_ptr<const ServedGarment>> FitCatalog::Garment(
    absl::string_view tenant, absl::string_view garment_id) {
  const std::string key = CacheKey({tenant, garment_id});
  if (auto hit = garments_.Get(key)) return hit->value;
  ASSIGN_OR_RETURN(std::string bytes, store_->GetGarment(tenant, garment_id));
  v1::Garment garment;
  if (!garment.ParseFromString(bytes)) {
    return absl::DataLossError(absl::StrCat("stored garment ", garment_id, " does not parse"));
  }
  auto served = std::make_shared<ServedGarment>();
  served->avatar_basis_id = garment.avatar_basis_id();
  v1::GarmentTopology& topology = served->topology;
  topology.set_garment_id(garment.id());
  topology.set_name(garment.name());
  topology.set_vertex_count(garment.template_mesh().vertex_count());
  *topology.mutable_faces() = garment.template_mesh();
  topology.mutable_faces()->clear_positions();
  *topology.mutable_texcoords() = garment.texcoords();
  *topology.mutable_face_texcoord_indices() = garment.face_texcoord_indices();
  for (const v1::GarmentSize& size : garment.sizes()) topology.add_sizes(size.name());
  ASSIGN_OR_RETURN(core::Mesh template_mesh, proto::MeshFromProto(garment.template_mesh()));
  const std::vector<uint32_t> order = core::SpatialOrder(template_mesh.positions);
  topology.mutable_wire_order()->Assign(order.begin(), order.end());
  size_t bytes_held = topology.ByteSizeLong();
  absl::StatusOr<pipeline::AdviceGarment> advice = pipeline::PrepareAdviceGarment(garment);
  if (advice.ok()) {
    bytes_held += sizeof(double) * 3 * static_cast<size_t>(advice->triangles.rows()) *
                  (advice->rest.size() + 1);
    served->advice = std::make_shared<const pipeline::AdviceGarment>(*std::move(advice));
  } else {
    served->advice_error = advice.status();
  }
  garments_.Put(key, {served, bytes_held, Now()});
  return served;
}

absl::StatusOr<std::shared_ptr<const ServedClothing>> FitCatalog::Clothing(
    const storage::ClothingBasisKey& key) {
  const std::string cache_key =
      CacheKey({key.tenant, key.garment_id, key.size, key.avatar_basis_id, key.method});
  const absl::Time now = Now();
  std::optional<ByteLruCache<ServedClothing>::Entry> hit = clothing_.Get(cache_key);
  if (hit.has_value() && now - hit->checked < options_.refresh) return hit->value;
  if (hit.has_value()) {
    ASSIGN_OR_RETURN(storage::ClothingBasisVersion current,
                     store_->GetCurrentClothingBasisVersion(key));
    if (current.version == hit->value->version) {
      clothing_.Touch(cache_key, now);
      return hit->value;
    }
  }
  ASSIGN_OR_RETURN(storage::ClothingBasisRecord record, store_->GetCurrentClothingBasis(key));
  v1::ClothingBasis basis;
  if (!basis.ParseFromString(record.bytes)) {
    return absl::DataLossError(
        absl::StrCat("stored clothing basis ", record.content_id, " does not parse"));
  }
  ASSIGN_OR_RETURN(clothing::ClothingFitter fitter, proto::ClothingFitterFromProto(basis));
  Eigen::VectorXd reach = Eigen::VectorXd::Zero(fitter.component_count());
  for (const v1::ClothingExample& example : basis.provenance().examples()) {
    for (int k = 0; k < std::min<int>(example.weights_size(), reach.size()); ++k) {
      reach(k) = std::max(reach(k), std::abs(example.weights(k)));
    }
  }
  auto served = std::make_shared<ServedClothing>(
      ServedClothing{std::move(fitter), record.version, record.content_id, std::move(reach)});
  // What the fitter holds, not the record: it keeps the basis in 16 bits, the record in floats.
  clothing_.Put(cache_key, {served, served->fitter.bytes(), now});
  return served;
}

absl::StatusOr<std::shared_ptr<const pipeline::LoadedAvatarBasis>> FitCatalog::CurrentAvatarBasis(
    absl::string_view tenant, absl::string_view population) {
  const std::string pointer_key = CacheKey({tenant, population});
  const absl::Time now = Now();
  std::string id;
  std::optional<ByteLruCache<std::string>::Entry> pointer = avatar_pointers_.Get(pointer_key);
  if (pointer.has_value() && now - pointer->checked < options_.refresh) {
    id = *pointer->value;
  } else {
    ASSIGN_OR_RETURN(id, store_->GetCurrentAvatarBasisId(tenant, population));
    avatar_pointers_.Put(pointer_key, {std::make_shared<std::string>(id), id.size(), now});
  }
  return AvatarBasis(id);
}

absl::StatusOr<std::shared_ptr<const pipeline::LoadedAvatarBasis>> FitCatalog::AvatarBasis(
    absl::string_view avatar_basis_id) {
  const std::string id(avatar_basis_id);
  const absl::Time now = Now();
  if (auto hit = avatar_bases_.Get(id)) return hit->value;
  ASSIGN_OR_RETURN(std::string bytes, store_->GetAvatarBasis(id));
  auto loaded = std::make_shared<pipeline::LoadedAvatarBasis>();
  if (!loaded->message.ParseFromString(bytes)) {
    return absl::DataLossError(absl::StrCat("stored avatar basis ", id, " does not parse"));
  }
  ASSIGN_OR_RETURN(loaded->pca, proto::PcaBasisFromProto(loaded->message));
  // The message (float32) and the decomposition (double) are both kept.
  avatar_bases_.Put(
      id,
      {loaded, bytes.size() + sizeof(double) * static_cast<size_t>(loaded->pca.components.size()),
       now});
  return loaded;
}

}  // namespace fitbase::fit
