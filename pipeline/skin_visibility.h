#ifndef FITBASE_PIPELINE_SKIN_VISIBILITY_H_
#define FITBASE_PIPELINE_SKIN_VISIBILITY_H_

#include <cstdint>

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

// reference: typically the drape on the customer's real body; candidate: a fast fit on the body
// it is shown with (for a clothing basis, the body of the weights). Both are framed on the
// union bounding box of the four meshes, at `height` pixels. Errors (INVALID_ARGUMENT): a
// missing or empty mesh, non-finite positions, a triangle index out of range, a height outside
// [16, 16384].
absl::StatusOr<SkinVisibility> MeasureVisibleSkin(const DressedBody& reference,
                                                  const DressedBody& candidate,
                                                  int height = kSkinViewHeight);

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
