#include "pipeline/size_advisor.h"

#include <cmath>
#include <limits>

#include "absl/strings/str_cat.h"
#include "body/body_model.h"
#include "body/body_skeleton.h"
#include "core/status_macros.h"
#include "proto/garment_codec.h"
#include "proto/mesh_codec.h"
#include "workers/size_grading.h"

namespace fitbase::pipeline {
namespace {

using body::BodyLandmarks;


// Rest lengths of every triangle edge, by triangle (TriangleEdgeLengths' layout).
clothing::TriangleEdgeLengths ByTriangle(const core::Triangles& triangles,
                                     const Eigen::VectorXd& lengths) {
  clothing::TriangleEdgeLengths out(triangles.rows(), 3);
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    for (int c = 0; c < 3; ++c) out(t, c) = lengths(3 * t + c);
  }
  return out;
}

std::vector<std::array<int32_t, 2>> TriangleEdges(const core::Triangles& triangles) {
  std::vector<std::array<int32_t, 2>> pairs;
  pairs.reserve(static_cast<size_t>(3 * triangles.rows()));
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    for (int c = 0; c < 3; ++c) pairs.push_back({triangles(t, c), triangles(t, (c + 1) % 3)});
  }
  return pairs;
}

// The widest garment is well under twice the girth of the body under it (a loose coat's hem
// at the hip is about 1.4x).
constexpr double kMaxGirthRatio = 2.0;

Eigen::Vector3d At(const core::Positions& p, int32_t v) { return p.row(v).transpose(); }

// The garment's length (cm): a trouser leg from the crotch down to its hem when it has legs,
// else the torso from the neck base down to its hem; the body's matching length beside it.
// NaN when the garment has neither.
std::pair<double, double> Length(const AdviceGarment& garment, const core::Positions& fitted,
                                 const core::Positions& body) {
  const double crotch = body(BodyLandmarks::kCrotch, 1);
  const double neck_base =
      (body(BodyLandmarks::kNeckFront, 1) + body(BodyLandmarks::kNeckBack, 1)) / 2;
  auto lowest = [&](const std::vector<int32_t>& vertices) {
    double y = std::numeric_limits<double>::infinity();
    for (int32_t v : vertices) y = std::min(y, fitted(v, 1));
    return y;
  };
  if (!garment.leg_vertices.empty()) {
    return {100 * (crotch - lowest(garment.leg_vertices)),
            100 * (crotch - body.col(1).minCoeff())};
  }
  if (!garment.torso_vertices.empty()) {
    return {100 * (neck_base - lowest(garment.torso_vertices)), 100 * (neck_base - crotch)};
  }
  return {std::nan(""), std::nan("")};
}

// The left sleeve's reach from the acromion along the arm (cm), and the wrist's.
std::pair<double, double> Sleeve(const AdviceGarment& garment, const core::Positions& fitted,
                                 const core::Positions& body) {
  if (garment.sleeve_vertices.empty()) return {std::nan(""), std::nan("")};
  const Eigen::Vector3d acromion = At(body, BodyLandmarks::kLeftAcromion);
  const Eigen::Vector3d wrist = At(body, BodyLandmarks::kLeftWrist);
  const Eigen::Vector3d axis = (wrist - acromion).normalized();
  double reach = -std::numeric_limits<double>::infinity();
  for (int32_t v : garment.sleeve_vertices) {
    reach = std::max(reach, (At(fitted, v) - acromion).dot(axis));
  }
  return {100 * reach, 100 * (wrist - acromion).norm()};
}

}  // namespace

absl::StatusOr<AdviceGarment> PrepareAdviceGarment(const v1::Garment& garment) {
  AdviceGarment out;
  if (!garment.garment_type().empty()) {
    ASSIGN_OR_RETURN(out.type, clothing::ParseGarmentType(garment.garment_type()));
  }
  ASSIGN_OR_RETURN(core::GarmentMesh tmpl, proto::GarmentTemplateFromProto(garment));
  const core::Positions& rest = tmpl.mesh.positions;
  out.triangles = core::Triangulate(tmpl.mesh.faces);
  ASSIGN_OR_RETURN(core::Positions axes, proto::LengthAxesFromProto(garment));
  ASSIGN_OR_RETURN(std::vector<body::BodyRegion> regions, proto::RegionsFromProto(garment));
  ASSIGN_OR_RETURN(core::Mesh mean, proto::MeshFromProto(garment.mean_avatar()));
  if (mean.vertex_count() < body::kBodyVertexCount) {
    return absl::InvalidArgumentError(absl::StrCat("garment ", garment.id(), "'s mean avatar has ",
                                                   mean.vertex_count(), " vertices"));
  }
  const core::Positions mean_body = mean.positions.topRows(body::kBodyVertexCount);
  // The body's left side is the left acromion's side of the centre plane.
  const double left = mean_body(BodyLandmarks::kLeftAcromion, 0) > 0 ? 1.0 : -1.0;
  for (int32_t v = 0; v < static_cast<int32_t>(regions.size()); ++v) {
    const bool on_left = rest(v, 0) * left > 0;
    switch (regions[v]) {
      case body::BodyRegion::kTorso:
        out.torso_vertices.push_back(v);
        break;
      case body::BodyRegion::kArms:
        if (on_left) out.sleeve_vertices.push_back(v);
        break;
      case body::BodyRegion::kLegs:
        if (on_left) out.leg_vertices.push_back(v);
        break;
      case body::BodyRegion::kFeet:
        break;
    }
  }
  const std::vector<std::array<int32_t, 2>> pairs = TriangleEdges(out.triangles);
  for (const v1::GarmentSize& size : garment.sizes()) {
    out.size_names.push_back(size.name());
    if (size.has_rest()) {
      ASSIGN_OR_RETURN(core::Mesh size_mesh, proto::MeshFromProto(size.rest()));
      if (size_mesh.vertex_count() != rest.rows()) {
        return absl::InvalidArgumentError(absl::StrCat("size ", size.name(), "'s mesh has ",
                                                       size_mesh.vertex_count(),
                                                       " vertices; the template ", rest.rows()));
      }
      Eigen::VectorXd lengths(static_cast<Eigen::Index>(pairs.size()));
      for (size_t e = 0; e < pairs.size(); ++e) {
        lengths(static_cast<Eigen::Index>(e)) =
            (size_mesh.positions.row(pairs[e][0]) - size_mesh.positions.row(pairs[e][1])).norm();
      }
      out.rest.push_back(ByTriangle(out.triangles, lengths));
    } else {
      out.rest.push_back(ByTriangle(
          out.triangles, workers::GradedRestLengths(rest, axes, pairs, size.grading_step())));
    }
  }
  const auto [length, body_length] = Length(out, rest, mean_body);
  out.design_length_cm = length - body_length;
  const auto [sleeve, arm] = Sleeve(out, rest, mean_body);
  out.design_sleeve_cm = sleeve - arm;
  return out;
}

absl::StatusOr<AdviceBody> MeasureAdviceBody(core::Positions positions,
                                             core::Triangles triangles) {
  constexpr body::Measurement kGirths[] = {
      body::Measurement::kBustGirth, body::Measurement::kWaistGirth,
      body::Measurement::kHipGirth, body::Measurement::kThighGirth,
      body::Measurement::kUpperArmGirth};
  std::array<std::optional<body::GirthPlace>, body::kMeasurementCount> places;
  ASSIGN_OR_RETURN(body::BodyMeasurements measurements,
                   body::MeasureBody(positions, triangles, kGirths, &places));
  std::array<AdviceBody::TorsoSection, body::kMeasurementCount> torso_sections;
  for (body::Measurement torso : {body::Measurement::kBustGirth, body::Measurement::kWaistGirth,
                                  body::Measurement::kHipGirth}) {
    const body::GirthPlace& place = *places[static_cast<int>(torso)];
    const body::PlaneSection section =
        body::SectionMesh(positions, triangles, place.point, place.normal);
    AdviceBody::TorsoSection& split = torso_sections[static_cast<int>(torso)];
    for (const auto& loop : section.loops) {
      // The torso's loop is the one that holds the measured point; the arms' lie beside it.
      const bool is_torso =
          loop.size() >= 3 && std::isfinite(body::GirthAround(
                                  {section.origin, section.u, section.v, {loop}, {}, {}},
                                  place.inside));
      for (const Eigen::Vector2d& q : loop) {
        (is_torso ? split.torso : split.others)
            .push_back(section.origin + q.x() * section.u + q.y() * section.v);
      }
    }
  }
  ASSIGN_OR_RETURN(core::TriangleBvh bvh, core::TriangleBvh::Build(positions, triangles));
  return AdviceBody{std::move(positions), std::move(triangles), measurements, places,
                    std::move(torso_sections), std::move(bvh)};
}

absl::StatusOr<SizeJudgement> JudgeSize(const AdviceGarment& garment, int size,
                                        const AdviceBody& body, const core::Positions& fitted) {
  if (size < 0 || size >= static_cast<int>(garment.rest.size())) {
    return absl::InvalidArgumentError(absl::StrCat("no size ", size));
  }
  if (garment.triangles.rows() == 0 || fitted.rows() <= garment.triangles.maxCoeff() ||
      !fitted.allFinite()) {
    return absl::InvalidArgumentError(absl::StrCat("the fitted garment has ", fitted.rows(),
                                                   " vertices, fewer than its faces use, or non-finite positions"));
  }
  const clothing::TriangleEdgeLengths& rest = garment.rest[size];
  SizeJudgement out;
  constexpr std::pair<clothing::FitRegion, body::Measurement> kGirths[] = {
      {clothing::FitRegion::kBust, body::Measurement::kBustGirth},
      {clothing::FitRegion::kWaist, body::Measurement::kWaistGirth},
      {clothing::FitRegion::kHip, body::Measurement::kHipGirth},
      {clothing::FitRegion::kThigh, body::Measurement::kThighGirth},
      {clothing::FitRegion::kUpperArm, body::Measurement::kUpperArmGirth}};
  for (const auto& [region, measurement] : kGirths) {
    const auto& place = body.places[static_cast<int>(measurement)];
    if (!place.has_value()) continue;
    // A limb's loop must go round that limb alone: not hold the other thigh too (shorts cut
    // low between the legs), nor the torso (a sleeve's section that runs into the body).
    std::vector<Eigen::Vector3d> outside;
    if (region == clothing::FitRegion::kThigh) {
      outside.push_back(place->inside.cwiseProduct(Eigen::Vector3d(-1, 1, 1)));
    } else if (region == clothing::FitRegion::kUpperArm) {
      outside.push_back(Eigen::Vector3d(0, place->inside.y(), place->inside.z()));
    }
    const AdviceBody::TorsoSection& split = body.torso_sections[static_cast<int>(measurement)];
    auto nearest = [](const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& x) {
      double best = std::numeric_limits<double>::infinity();
      for (const Eigen::Vector3d& p : points) best = std::min(best, (p - x).squaredNorm());
      return best;
    };
    std::function<bool(const Eigen::Vector3d&)> counts;
    if (!split.torso.empty() && !split.others.empty()) {
      counts = [&](const Eigen::Vector3d& x) {
        return nearest(split.torso, x) <= nearest(split.others, x);
      };
    }
    const std::optional<clothing::GarmentGirth> girth =
        clothing::GarmentGirthAt(fitted, garment.triangles, rest, *place, outside, counts);
    const double body_girth = body.measurements[static_cast<int>(measurement)];
    // Twice the body's girth is no garment's ease there but a section that caught more than
    // that part of the body; the region is left unjudged rather than judged wrong.
    if (!girth.has_value() || girth->rest > kMaxGirthRatio * body_girth) continue;
    clothing::RegionFitValue value{.region = region};
    value.body_cm = 100 * body_girth;
    value.garment_cm = 100 * girth->rest;
    value.ease_cm = value.garment_cm - value.body_cm;
    value.stretch_pct = 100 * girth->stretch;
    out.regions.push_back(value);
  }
  const auto [length, body_length] = Length(garment, fitted, body.positions);
  if (std::isfinite(length)) {
    out.regions.push_back({.region = clothing::FitRegion::kGarmentLength,
                           .body_cm = body_length,
                           .garment_cm = length,
                           .ease_cm = length - body_length,
                           .design_ease_cm = garment.design_length_cm});
  }
  const auto [sleeve, arm] = Sleeve(garment, fitted, body.positions);
  if (std::isfinite(sleeve)) {
    out.regions.push_back({.region = clothing::FitRegion::kSleeveLength,
                           .body_cm = arm,
                           .garment_cm = sleeve,
                           .ease_cm = sleeve - arm,
                           .design_ease_cm = garment.design_sleeve_cm});
  }
  clothing::JudgeRegions(garment.type, out.regions);
  out.ease_mm = clothing::VertexEaseMm(fitted, body.bvh, /*max_mm=*/200);
  out.stretch_pct = clothing::VertexStretchPercent(fitted, garment.triangles, rest);
  return out;
}

v1::SizeAdvice AssembleAdvice(const AdviceGarment& garment, const std::vector<int>& sizes,
                              const std::vector<SizeJudgement>& judged, bool with_maps) {
  std::vector<std::string> names;
  std::vector<std::vector<clothing::RegionFitValue>> values;
  for (size_t i = 0; i < sizes.size(); ++i) {
    names.push_back(garment.size_names[sizes[i]]);
    values.push_back(judged[i].regions);
  }
  const clothing::SizeRecommendation recommendation =
      clothing::RecommendSize(garment.type, names, values);
  v1::SizeAdvice advice;
  advice.set_garment_type(std::string(clothing::GarmentTypeName(garment.type)));
  if (recommendation.best >= 0) advice.set_recommended_size(names[recommendation.best]);
  advice.set_confidence(recommendation.confidence);
  for (const std::string& reason : recommendation.reasons) advice.add_reasons(reason);
  for (size_t i = 0; i < sizes.size(); ++i) {
    v1::SizeFit* fit = advice.add_sizes();
    fit->set_size(names[i]);
    fit->set_verdict(std::string(clothing::VerdictName(recommendation.overall[i])));
    fit->set_summary(recommendation.summaries[i]);
    for (const clothing::RegionFitValue& value : judged[i].regions) {
      v1::RegionFit* region = fit->add_regions();
      region->set_region(std::string(clothing::FitRegionName(value.region)));
      region->set_body_cm(value.body_cm);
      region->set_garment_cm(value.garment_cm);
      region->set_ease_cm(value.ease_cm);
      region->set_stretch_pct(value.stretch_pct);
      region->set_verdict(std::string(clothing::VerdictName(value.verdict)));
    }
    if (with_maps) {
      fit->mutable_ease_mm()->Assign(judged[i].ease_mm.data(),
                                     judged[i].ease_mm.data() + judged[i].ease_mm.size());
      fit->mutable_stretch_pct()->Assign(
          judged[i].stretch_pct.data(),
          judged[i].stretch_pct.data() + judged[i].stretch_pct.size());
    }
  }
  return advice;
}

}  // namespace fitbase::pipeline
