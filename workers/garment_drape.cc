#include "workers/garment_drape.h"

#include <chrono>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "body/body_model.h"
#include "core/mhclo_binding.h"
#include "core/status_macros.h"
#include "core/triangle_bvh.h"
#include "proto/garment_codec.h"
#include "proto/mesh_codec.h"
#include "workers/size_grading.h"

namespace fitbase::workers {
namespace {

constexpr double kMmPerMeter = 1000.0;

// What every fit of one garment needs, decoded and validated from the message.
struct PreparedGarment {
  core::GarmentMesh template_mesh;
  ClothModel model;
  std::vector<body::BodyRegion> regions;
  core::Positions mean_full;  // 19,158 x 3.
  core::Positions mean_body;  // 13,380 x 3.
  core::Triangles body_triangles;
  Eigen::VectorXd edge_rest;
  Eigen::VectorXd hinge_rest;
  Supports supports;
};

absl::StatusOr<PreparedGarment> Prepare(const v1::Garment& garment, absl::string_view size,
                                        const core::Positions& target_body,
                                        double areal_density) {
  PreparedGarment g;
  ASSIGN_OR_RETURN(const v1::GarmentSize* garment_size, FindGarmentSize(garment, size));
  ASSIGN_OR_RETURN(g.template_mesh, proto::GarmentTemplateFromProto(garment));
  ASSIGN_OR_RETURN(core::Mesh mean, proto::MeshFromProto(garment.mean_avatar()));
  if (mean.vertex_count() != body::kFullVertexCount) {
    return absl::InvalidArgumentError(absl::StrCat("garment's mean avatar has ",
                                                   mean.vertex_count(), " vertices, not ",
                                                   body::kFullVertexCount));
  }
  if (target_body.rows() != body::kBodyVertexCount) {
    return absl::InvalidArgumentError(absl::StrCat("avatar has ", target_body.rows(),
                                                   " vertices; a ", body::kBodyTopologyId,
                                                   " avatar has ", body::kBodyVertexCount));
  }
  if (!target_body.allFinite()) return absl::InvalidArgumentError("avatar has non-finite positions");
  g.mean_full = std::move(mean.positions);
  g.mean_body = g.mean_full.topRows(body::kBodyVertexCount);
  g.body_triangles = core::Triangulate(body::BodyFacesOf(mean.faces));
  const core::Positions& rest = g.template_mesh.mesh.positions;
  ASSIGN_OR_RETURN(g.model, BuildClothModel(rest, g.template_mesh.mesh.faces, areal_density));
  ASSIGN_OR_RETURN(g.regions, proto::RegionsFromProto(garment));
  ASSIGN_OR_RETURN(g.supports, FindSupports(g.model, rest, g.mean_body));
  if (garment.has_cuffs()) {
    ASSIGN_OR_RETURN(
        g.supports.cuffs,
        FindCuffs(g.model, rest, g.regions, g.mean_body, g.body_triangles,
                  {.sleeves = garment.cuffs().sleeves(), .legs = garment.cuffs().legs()}));
  }
  if (garment_size->has_rest()) {
    ASSIGN_OR_RETURN(core::Mesh size_mesh, proto::MeshFromProto(garment_size->rest()));
    if (size_mesh.vertex_count() != rest.rows()) {
      return absl::InvalidArgumentError(absl::StrCat("size ", size, " mesh has ",
                                                     size_mesh.vertex_count(), " vertices; the template ",
                                                     rest.rows()));
    }
    g.edge_rest = PairLengths(size_mesh.positions, g.model.edges);
    g.hinge_rest = HingeAngles(size_mesh.positions, g.model.hinges);
  } else {
    // Size M is the template as it sits on the mean avatar: the garment fits that body.
    ASSIGN_OR_RETURN(core::Positions axes, proto::LengthAxesFromProto(garment));
    const int step = garment_size->grading_step();
    g.edge_rest = GradedRestLengths(rest, axes, g.model.edges, step);
    // Grading scales the garment nearly uniformly, which keeps its angles.
    g.hinge_rest = HingeAngles(rest, g.model.hinges);
  }
  return g;
}

v1::DrapeReport ReportOf(const v1::Garment& garment, absl::string_view size,
                         absl::string_view method, const FitMetrics& m) {
  v1::DrapeReport r;
  r.set_garment_id(garment.id());
  r.set_size(std::string(size));
  r.set_method(std::string(method));
  r.set_vertex_count(static_cast<uint32_t>(m.vertex_count));
  r.set_penetration_below_0mm(m.penetration_below_0mm);
  r.set_penetration_below_1mm(m.penetration_below_1mm);
  r.set_strain_mean(m.strain_mean);
  r.set_strain_p99(m.strain_p99);
  r.set_strain_max(m.strain_max);
  r.set_stretch_p99(m.stretch_p99);
  r.set_compression_p99(m.compression_p99);
  r.set_overstretched(m.overstretched);
  r.set_ease_mean_mm(m.ease_mean_mm);
  r.set_ease_p50_mm(m.ease_p50_mm);
  r.set_ease_p95_mm(m.ease_p95_mm);
  for (const RegionEase& e : m.region_ease) {
    v1::RegionEase* region = r.add_region_ease();
    region->set_region(std::string(body::BodyRegionName(e.region)));
    region->set_vertex_count(static_cast<uint32_t>(e.vertex_count));
    region->set_ease_mean_mm(e.mean_mm);
    region->set_ease_p95_mm(e.p95_mm);
  }
  return r;
}

// How close the cuffs sit to the skin of `body` (the avatar's surface): their vertices' mean
// distance from it. `positions`: V x 3, m.
void SetCuffGap(const PreparedGarment& g, const core::Positions& positions,
                const core::TriangleBvh& body, v1::DrapeReport* report) {
  if (g.supports.cuffs.empty()) return;
  double sum = 0;
  int count = 0;
  for (int32_t cuff : g.supports.cuffs) {
    for (int32_t v : g.model.openings[cuff].vertices) {
      const core::SurfacePoint hit = body.Closest(positions.row(v).transpose(), 1.0);
      if (!hit.found) continue;
      sum += std::abs(hit.signed_distance);
      ++count;
    }
  }
  report->set_cuff_count(static_cast<uint32_t>(g.supports.cuffs.size()));
  if (count > 0) report->set_cuff_gap_mm(kMmPerMeter * sum / count);
}

void SetSupports(const SupportHeights& supports, v1::DrapeReport* report) {
  if (supports.waistband_above_navel) {
    report->set_waistband_above_navel_mm(kMmPerMeter * *supports.waistband_above_navel);
  }
  if (supports.waistband_crotch_to_navel) {
    report->set_waistband_crotch_to_navel(*supports.waistband_crotch_to_navel);
  }
  if (supports.collar_above_neck_base) {
    report->set_collar_above_neck_base_mm(kMmPerMeter * *supports.collar_above_neck_base);
  }
  if (supports.hem_above_ankle) {
    report->set_hem_above_ankle_mm(kMmPerMeter * *supports.hem_above_ankle);
  }
}

}  // namespace

absl::StatusOr<const v1::GarmentSize*> FindGarmentSize(const v1::Garment& garment,
                                                absl::string_view size) {
  std::vector<std::string> names;
  for (const v1::GarmentSize& s : garment.sizes()) {
    if (s.name() == size) return &s;
    names.push_back(s.name());
  }
  return absl::NotFoundError(absl::StrCat("garment ", garment.name(), " has no size '", size,
                                          "'; its sizes are ", absl::StrJoin(names, ", ")));
}

absl::StatusOr<GarmentFit> DrapeGarment(const v1::Garment& garment, absl::string_view size,
                                        const core::Positions& target_body,
                                        const ClothSettings& settings,
                                        const DrapeSchedule& schedule) {
  ASSIGN_OR_RETURN(PreparedGarment g,
                   Prepare(garment, size, target_body, settings.areal_density));
  DrapeInput input{.model = &g.model,
                   .start = g.template_mesh.mesh.positions,
                   .edge_rest = g.edge_rest,
                   .hinge_rest = g.hinge_rest,
                   .supports = g.supports,
                   .regions = g.regions,
                   .mean_body = g.mean_body,
                   .target_body = target_body,
                   .body_triangles = g.body_triangles};
  ASSIGN_OR_RETURN(DrapeResult drape, Drape(input, settings, schedule));
  GarmentFit fit{std::move(drape.positions), ReportOf(garment, size, "drape", drape.metrics)};
  SetSupports(
      MeasureSupports(g.model, g.supports, g.mean_body, fit.positions, target_body),
      &fit.report);
  if (!g.supports.cuffs.empty()) {
    ASSIGN_OR_RETURN(core::TriangleBvh body,
                     core::TriangleBvh::Build(target_body, g.body_triangles));
    SetCuffGap(g, fit.positions, body, &fit.report);
  }
  fit.report.set_converged_max_move_mm(drape.converged_max_move_mm);
  fit.report.set_steps(static_cast<uint32_t>(drape.steps));
  fit.report.set_seconds(drape.seconds);
  fit.report.set_carried_girth_ratio(drape.carried_girth_ratio);
  fit.report.set_tie_factor(drape.tie_factor);
  return fit;
}

absl::StatusOr<GarmentFit> GeometricFit(const v1::Garment& garment, absl::string_view size,
                                        const core::Positions& target_body) {
  if (!garment.has_binding()) {
    return absl::FailedPreconditionError(absl::StrCat(
        "garment ", garment.name(), " was imported without a .mhclo binding: no geometric fit"));
  }
  const auto start = std::chrono::steady_clock::now();
  ASSIGN_OR_RETURN(PreparedGarment g,
                   Prepare(garment, size, target_body, ClothSettings{}.areal_density));
  ASSIGN_OR_RETURN(core::MhcloBinding binding,
                   proto::MhcloBindingFromProto(garment.binding(), g.template_mesh.mesh.vertex_count(),
                                                body::kFullVertexCount));
  // Helper and joint vertices follow the body surface nearest them on the mean avatar.
  ASSIGN_OR_RETURN(core::TriangleBvh mean_bvh, core::TriangleBvh::Build(g.mean_body, g.body_triangles));
  core::Positions full = g.mean_full;
  full.topRows(body::kBodyVertexCount) = target_body;
  const core::Positions displacement = target_body - g.mean_body;
  for (Eigen::Index v = body::kBodyVertexCount; v < full.rows(); ++v) {
    const core::SurfacePoint hit = mean_bvh.Closest(g.mean_full.row(v).transpose(), 10.0);
    const auto tri = g.body_triangles.row(hit.triangle);
    for (int k = 0; k < 3; ++k) full.row(v) += hit.barycentric(k) * displacement.row(tri(k));
  }
  GarmentFit fit;
  fit.positions = core::ApplyMhclo(binding, full);
  ASSIGN_OR_RETURN(core::TriangleBvh target_bvh, core::TriangleBvh::Build(target_body, g.body_triangles));
  fit.report = ReportOf(garment, size, "geometric",
                        MeasureFit(fit.positions, g.model.edges, g.edge_rest, target_bvh, g.regions));
  SetSupports(
      MeasureSupports(g.model, g.supports, g.mean_body, fit.positions, target_body),
      &fit.report);
  SetCuffGap(g, fit.positions, target_bvh, &fit.report);
  fit.report.set_seconds(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return fit;
}

}  // namespace fitbase::workers
