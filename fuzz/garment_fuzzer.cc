// A stored garment (`.fbg`, the store's garment records): the v1::Garment message parsed, then
// what the fit service and the drape worker decode of it: the topology the fit service sends
// (template mesh and its spatial wire order), every part through its proto codec, and what a
// drape prepares from them (workers/garment_drape.cc): the mean avatar's body triangles, the
// binding applied to the mean avatar, the cloth model, and per size its rest lengths, graded or
// from the size's own mesh. The drape and the geometric fit themselves are not run: their body
// queries take seconds per input here.
#include <cstdint>

#include "body/body_model.h"
#include "core/mhclo_binding.h"
#include "core/vertex_order.h"
#include "fitbase/v1/garment.pb.h"
#include "proto/garment_codec.h"
#include "proto/mesh_codec.h"
#include "workers/cloth_model.h"
#include "workers/cloth_solver.h"
#include "workers/size_grading.h"

namespace fitbase {
namespace {

// Sizes are prepared for at most this many.
constexpr int kMaxSizes = 4;

void Prepare(const v1::Garment& garment) {
  auto template_mesh = proto::MeshFromProto(garment.template_mesh());
  if (template_mesh.ok()) (void)core::SpatialOrder(template_mesh->positions);
  (void)proto::RegionsFromProto(garment);
  auto mean = proto::MeshFromProto(garment.mean_avatar());
  const bool mean_ok = mean.ok() && mean->vertex_count() == body::kFullVertexCount;
  if (mean_ok) (void)core::Triangulate(body::BodyFacesOf(mean->faces));
  auto garment_mesh = proto::GarmentTemplateFromProto(garment);
  if (!garment_mesh.ok()) return;
  const core::Positions& rest = garment_mesh->mesh.positions;
  if (garment.has_binding()) {
    auto binding =
        proto::MhcloBindingFromProto(garment.binding(), rest.rows(), body::kFullVertexCount);
    if (binding.ok() && mean_ok) (void)core::ApplyMhclo(*binding, mean->positions);
  }
  auto model = workers::BuildClothModel(rest, garment_mesh->mesh.faces,
                                        workers::ClothSettings{}.areal_density);
  if (!model.ok()) return;
  auto axes = proto::LengthAxesFromProto(garment);
  for (int s = 0; s < garment.sizes_size() && s < kMaxSizes; ++s) {
    const v1::GarmentSize& size = garment.sizes(s);
    if (size.has_rest()) {
      auto size_mesh = proto::MeshFromProto(size.rest());
      if (!size_mesh.ok() || size_mesh->vertex_count() != rest.rows()) continue;
      (void)workers::PairLengths(size_mesh->positions, model->edges);
      (void)workers::HingeAngles(size_mesh->positions, model->hinges);
    } else if (axes.ok()) {
      (void)workers::GradedRestLengths(rest, *axes, model->edges, size.grading_step());
      (void)workers::HingeAngles(rest, model->hinges);
    }
  }
}

}  // namespace
}  // namespace fitbase

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fitbase::v1::Garment garment;
  if (garment.ParseFromArray(data, static_cast<int>(size))) fitbase::Prepare(garment);
  return 0;
}
