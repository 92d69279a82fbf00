#include "pipeline/skin_visibility.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "Eigen/Geometry"
#include "absl/strings/str_cat.h"
#include "core/mesh_render.h"
#include "core/status_macros.h"

namespace fitbase::pipeline {
namespace {

constexpr int32_t kBodyLayer = 0;
constexpr int32_t kGarmentLayer = 1;

core::Mesh TriangleMesh(const core::Positions& positions, const core::Triangles& triangles) {
  core::Mesh mesh;
  mesh.positions = positions;
  mesh.faces.sizes.assign(static_cast<size_t>(triangles.rows()), 3);
  mesh.faces.indices.assign(triangles.data(), triangles.data() + triangles.size());
  return mesh;
}

absl::Status CheckScene(const DressedBody& scene, absl::string_view name) {
  if (scene.body == nullptr || scene.body_triangles == nullptr || scene.garment == nullptr ||
      scene.garment_triangles == nullptr) {
    return absl::InvalidArgumentError(absl::StrCat("the ", name, " scene misses a mesh"));
  }
  if (scene.body->rows() == 0 || scene.garment->rows() == 0 || scene.body_triangles->rows() == 0 ||
      scene.garment_triangles->rows() == 0) {
    return absl::InvalidArgumentError(absl::StrCat("the ", name, " scene has an empty mesh"));
  }
  if (!scene.body->allFinite() || !scene.garment->allFinite()) {
    return absl::InvalidArgumentError(absl::StrCat("the ", name, " scene is not finite"));
  }
  return absl::OkStatus();
}

void Extend(const core::Positions& positions, Eigen::AlignedBox3d& box) {
  box.extend(positions.colwise().minCoeff().transpose());
  box.extend(positions.colwise().maxCoeff().transpose());
}

}  // namespace

absl::StatusOr<SkinVisibility> MeasureSkinThroughCloth(const DressedBody& drape, int height) {
  RETURN_IF_ERROR(CheckScene(drape, "drape"));
  Eigen::AlignedBox3d frame;
  Extend(*drape.body, frame);
  Extend(*drape.garment, frame);
  const core::RenderOptions options{.height = height, .frame = frame};
  std::vector<core::RenderLayer> layers(2);
  layers[kBodyLayer].mesh = TriangleMesh(*drape.body, *drape.body_triangles);
  layers[kGarmentLayer].mesh = TriangleMesh(*drape.garment, *drape.garment_triangles);
  ASSIGN_OR_RETURN(const core::RenderedImage dressed, core::RenderFrontAndSide(layers, options));
  layers.erase(layers.begin());
  ASSIGN_OR_RETURN(const core::RenderedImage cloth, core::RenderFrontAndSide(layers, options));
  SkinVisibility result;
  for (size_t i = 0; i < cloth.layer_index.size(); ++i) {
    if (cloth.layer_index[i] < 0) continue;
    const bool skin = dressed.layer_index[i] == kBodyLayer;
    if (skin && dressed.depth[i] - cloth.depth[i] >= kClothCoverDepth) continue;
    ++result.cloth_pixels;
    result.skin_pixels += skin;
  }
  return result;
}

absl::StatusOr<SkinVisibility> MeasureVisibleSkin(const DressedBody& reference,
                                                  const DressedBody& candidate, int height,
                                                  SkinPicture* picture) {
  RETURN_IF_ERROR(CheckScene(reference, "reference"));
  RETURN_IF_ERROR(CheckScene(candidate, "candidate"));
  Eigen::AlignedBox3d frame;
  for (const DressedBody* scene : {&reference, &candidate}) {
    Extend(*scene->body, frame);
    Extend(*scene->garment, frame);
  }
  const core::RenderOptions options{.height = height, .frame = frame};
  std::vector<core::RenderedImage> images;
  for (const DressedBody* scene : {&reference, &candidate}) {
    // The body is layer 0 and the garment layer 1, drawn last so that where they touch (equal
    // depth) the garment shows, as in the drape.
    std::vector<core::RenderLayer> layers(2);
    layers[kBodyLayer].mesh = TriangleMesh(*scene->body, *scene->body_triangles);
    layers[kGarmentLayer].mesh = TriangleMesh(*scene->garment, *scene->garment_triangles);
    ASSIGN_OR_RETURN(core::RenderedImage image, core::RenderFrontAndSide(layers, options));
    images.push_back(std::move(image));
  }
  SkinVisibility result;
  const core::RenderedImage& drape = images[0];
  const core::RenderedImage& fit = images[1];
  const int band = static_cast<int>(std::ceil(kClothEdgeBand * drape.pixels_per_meter));
  // Whether the reference shows anything but its garment within `band` pixels of (x, y); the
  // image's border counts as an edge.
  const auto near_edge = [&](int x, int y) {
    for (int v = y - band; v <= y + band; ++v) {
      for (int u = x - band; u <= x + band; ++u) {
        if (u < 0 || v < 0 || u >= drape.width || v >= drape.height ||
            drape.LayerAt(u, v) != kGarmentLayer) {
          return true;
        }
      }
    }
    return false;
  };
  if (picture != nullptr) {
    *picture = SkinPicture{.frame = frame,
                           .width = drape.width,
                           .height = drape.height,
                           .pixels = std::vector<SkinPixel>(drape.layer_index.size())};
  }
  for (int y = 0; y < drape.height; ++y) {
    for (int x = 0; x < drape.width; ++x) {
      if (drape.LayerAt(x, y) != kGarmentLayer) continue;
      ++result.cloth_pixels;
      if (fit.LayerAt(x, y) != kBodyLayer) continue;
      ++result.skin_pixels;
      const bool edge = near_edge(x, y);
      result.edge_skin_pixels += edge;
      if (picture != nullptr) {
        picture->pixels[y * drape.width + x] = edge ? SkinPixel::kEdge : SkinPixel::kInside;
      }
    }
  }
  return result;
}

GarmentEdges FindGarmentEdges(const core::Triangles& triangles) {
  std::map<std::pair<int32_t, int32_t>, int> uses;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    for (int c = 0; c < 3; ++c) {
      const int32_t a = triangles(t, c);
      const int32_t b = triangles(t, (c + 1) % 3);
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  std::set<int32_t> open;
  for (const auto& [edge, count] : uses) {
    if (count != 1) continue;
    open.insert(edge.first);
    open.insert(edge.second);
  }
  GarmentEdges edges;
  edges.vertices.assign(open.begin(), open.end());
  edges.neighbours.resize(edges.vertices.size());
  edges.along.resize(edges.vertices.size());
  const auto add = [&edges](int32_t v, int32_t neighbour, bool open_edge) {
    const auto at = std::lower_bound(edges.vertices.begin(), edges.vertices.end(), v);
    if (at == edges.vertices.end() || *at != v) return;
    const auto e = at - edges.vertices.begin();
    edges.neighbours[e].push_back(neighbour);
    if (open_edge) edges.along[e].push_back(neighbour);
  };
  for (const auto& [edge, count] : uses) {
    add(edge.first, edge.second, count == 1);
    add(edge.second, edge.first, count == 1);
  }
  return edges;
}

Eigen::VectorXd EdgeRetreat(const GarmentEdges& edges, const core::Positions& reference,
                            const core::Positions& candidate) {
  Eigen::VectorXd retreat(static_cast<Eigen::Index>(edges.vertices.size()));
  for (size_t e = 0; e < edges.vertices.size(); ++e) {
    const int32_t v = edges.vertices[e];
    Eigen::RowVector3d inward = Eigen::RowVector3d::Zero();
    for (const int32_t n : edges.neighbours[e]) inward += reference.row(n) - reference.row(v);
    // A vertex where more than two open edges meet (a seam's corner) has no one edge line.
    if (edges.along[e].size() == 2) {
      const Eigen::RowVector3d line =
          reference.row(edges.along[e][1]) - reference.row(edges.along[e][0]);
      const double line_length = line.norm();
      if (line_length > 0) inward -= inward.dot(line) / (line_length * line_length) * line;
    }
    const double length = inward.norm();
    retreat[static_cast<Eigen::Index>(e)] =
        length > 0 ? (candidate.row(v) - reference.row(v)).dot(inward) / length
                   : std::numeric_limits<double>::quiet_NaN();
  }
  return retreat;
}

}  // namespace fitbase::pipeline
