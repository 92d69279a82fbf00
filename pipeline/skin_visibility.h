#ifndef FITBASE_PIPELINE_SKIN_VISIBILITY_H_
#define FITBASE_PIPELINE_SKIN_VISIBILITY_H_

#include <cstdint>
#include <vector>

#include "Eigen/Geometry"
#include "absl/status/statusor.h"
#include "core/mesh.h"

namespace fitbase::pipeline {

// The front and side pictures the visible-skin figure is judged on: about a shopper's screen.
inline constexpr int kSkinViewHeight = 600;

// Skin through cloth, as a shopper sees it: pixels of the front and side views (orthographic,
// z-buffered, one framing for both scenes) where the reference shows the garment and the
// candidate shows the body, over the pixels where the reference shows the garment; of them,
// those along the reference garment's edges apart (kClothEdgeBand).
struct SkinVisibility {
  int64_t cloth_pixels = 0;  // The reference's garment pixels.
  int64_t skin_pixels = 0;   // Of those, the candidate's body pixels.
  // Of those, the ones within kClothEdgeBand of a pixel where the reference shows no garment
  // (MeasureVisibleSkin only).
  int64_t edge_skin_pixels = 0;

  double share() const { return Share(skin_pixels); }
  // Skin away from the garment's edges: the body through the cloth itself.
  double inside_share() const { return Share(skin_pixels - edge_skin_pixels); }

 private:
  double Share(int64_t pixels) const {
    return cloth_pixels > 0 ? static_cast<double>(pixels) / static_cast<double>(cloth_pixels)
                            : 0.0;
  }
};

// A fit whose hem, cuff, neckline or waistband lies a few millimetres from the drape's shows a
// line of skin along it, a pixel or two wide at 600 px (a pixel is about 3 mm): that is the
// edge in another place, not the body through the cloth. Skin pixels this close (m) to where
// the reference's garment ends are counted apart.
inline constexpr double kClothEdgeBand = 0.01;

// A garment worn on a body: positions (m, +Y up, +Z front) and their triangles.
struct DressedBody {
  const core::Positions* body = nullptr;  // B x 3.
  const core::Triangles* body_triangles = nullptr;
  const core::Positions* garment = nullptr;  // V x 3.
  const core::Triangles* garment_triangles = nullptr;
};

// What a pixel of the reference's cloth shows in the candidate, for a picture of where the
// visible skin is.
enum class SkinPixel : uint8_t {
  kNone,    // Not the reference's cloth, or the candidate's cloth covers it.
  kEdge,    // The candidate's skin, within kClothEdgeBand of the reference garment's edge.
  kInside,  // The candidate's skin, farther in: the body through the cloth.
};

// Where MeasureVisibleSkin found skin. A render with options.frame = frame and the same height
// maps every world point to the same pixel (core::RenderOptions), so the pixels can be marked
// on a picture of either scene.
struct SkinPicture {
  Eigen::AlignedBox3d frame;     // m.
  int width = 0;
  int height = 0;
  std::vector<SkinPixel> pixels;  // height x width, rows from the top.
};

// reference: typically the drape on the customer's real body; candidate: a fast fit on the body
// it is shown with (for a clothing basis, the body of the weights). Both are framed on the
// union bounding box of the four meshes, at `height` pixels; `picture`, if given, receives
// where the skin is. Errors (INVALID_ARGUMENT): a missing or empty mesh, non-finite positions,
// a triangle index out of range, a height outside [16, 16384].
absl::StatusOr<SkinVisibility> MeasureVisibleSkin(const DressedBody& reference,
                                                  const DressedBody& candidate,
                                                  int height = kSkinViewHeight,
                                                  SkinPicture* picture = nullptr);

// A garment's open edges (edges of one triangle): its hems, cuffs, necklines and waistbands.
struct GarmentEdges {
  std::vector<int32_t> vertices;                // Ascending.
  std::vector<std::vector<int32_t>> neighbours;  // Per vertex: those it shares an edge with.
  std::vector<std::vector<int32_t>> along;       // Per vertex: those it shares an open edge with.
};

// triangles: F x 3 vertex indices >= 0 of one garment.
GarmentEdges FindGarmentEdges(const core::Triangles& triangles);

// How far each edge vertex of `candidate` lies back into the cloth from `reference`'s (m; one
// per edges.vertices): its move along the reference's direction into the cloth there, from the
// vertex towards its neighbours, square to the edge (the part along the line through its two
// neighbours on the edge taken out). +: a hem higher, a neckline lower, a line of skin uncovered
// along it; -: the edge out past the reference's, which uncovers none. NaN where that direction
// vanishes. reference, candidate: V x 3 (m), the garment's vertex order.
Eigen::VectorXd EdgeRetreat(const GarmentEdges& edges, const core::Positions& reference,
                            const core::Positions& candidate);

// How far in front of its garment a body surface may lie and still be the cloth's own place:
// more than any body point pokes through a drape, less than the gap between a limb and the
// cloth behind it that it hides in the views (an arm before the side of a top), m.
inline constexpr double kClothCoverDepth = 0.02;

// Skin through a garment's own cloth, as a shopper sees it: the front and side views of the
// drape (orthographic, z-buffered) and of its garment alone, one framing for both. Cloth pixels
// are those the garment covers where the body in front of it, if any, lies less than
// kClothCoverDepth before it; skin pixels are those of them where the body shows. A body part
// farther in front (a limb) hides the cloth legitimately and counts for neither. Errors
// (INVALID_ARGUMENT) as MeasureVisibleSkin's.
absl::StatusOr<SkinVisibility> MeasureSkinThroughCloth(const DressedBody& drape,
                                                       int height = kSkinViewHeight);

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_SKIN_VISIBILITY_H_
