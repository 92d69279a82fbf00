#ifndef FITBASE_CLOTHING_SIZE_ADVICE_H_
#define FITBASE_CLOTHING_SIZE_ADVICE_H_

#include <span>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace fitbase::clothing {

// Where a size is judged against the body (the body's landmark planes, MeasureBody).
enum class FitRegion {
  kBust = 0,       // Bust (men: chest) girth.
  kWaist,          // Natural waist girth.
  kHip,            // Hip girth.
  kThigh,          // Left thigh girth.
  kUpperArm,       // Left upper arm girth.
  kGarmentLength,  // Trouser leg (crotch to hem) when the garment has legs, else torso length.
  kSleeveLength,   // Left acromion to the cuff, along the arm.
};
inline constexpr int kFitRegionCount = 7;
absl::string_view FitRegionName(FitRegion region);  // "bust", "upper_arm", ...
bool IsGirth(FitRegion region);

// The ease a garment is cut with, which sets what "regular" means (pattern-making practice).
enum class GarmentType { kKnit, kFitted, kShirt, kJacket };
absl::string_view GarmentTypeName(GarmentType type);
// "knit", "fitted", "shirt", "jacket"; INVALID_ARGUMENT naming the known ones otherwise.
absl::StatusOr<GarmentType> ParseGarmentType(absl::string_view name);

enum class Verdict { kTight, kFitted, kRegular, kLoose, kShort, kLong };
absl::string_view VerdictName(Verdict verdict);

// Girth ease bands, cm (garment rest girth minus body girth): below tight_below is tight,
// then fitted up to regular_from, regular up to loose_above, loose beyond. README "Size
// advice" prints the whole table.
struct EaseBand {
  double tight_below;
  double regular_from;
  double loose_above;
};
EaseBand GirthEaseBand(GarmentType type, FitRegion region);  // A girth region.
// A length is short or long when it differs by more than this from its design ease (the
// template size's on the mean body), cm.
inline constexpr double kLengthToleranceCm = 3.0;

// One region of one size, cm and %.
struct RegionFitValue {
  FitRegion region;
  double body_cm = 0;
  double garment_cm = 0;
  double ease_cm = 0;
  double stretch_pct = 0;
  double design_ease_cm = 0;  // Lengths: the template size's ease on the mean body.
  Verdict verdict = Verdict::kRegular;
};

// Sets the verdict of each region of `values` from its ease.
void JudgeRegions(GarmentType type, std::span<RegionFitValue> values);

// A size's mismatch with the body: 0 when every region is regular; each cm a girth lies
// below its regular band costs 1 (3 more below tight), above it 1; a length 0.25 per cm
// beyond its tolerance.
double SizePenalty(GarmentType type, std::span<const RegionFitValue> values);

struct SizeRecommendation {
  int best = -1;                       // Index into the sizes.
  double confidence = 0;               // 0..1.
  std::vector<std::string> reasons;    // Sentences for the shopper.
  std::vector<Verdict> overall;        // Per size: its worst region's verdict, else regular.
  std::vector<std::string> summaries;  // Per size: "S: tight at the bust (-2.1 cm)".
};

// sizes[i]: the judged regions of size names[i], smallest size first. The best size has the
// lowest penalty; among sizes without any, the one closest to the middle of the regular bands.
// Confidence grows with the margin to the next best (0.5 at a tie, 0.82 at 2 cm, 0.96 at 5).
SizeRecommendation RecommendSize(GarmentType type, std::span<const std::string> names,
                                 std::span<const std::vector<RegionFitValue>> sizes);

}  // namespace fitbase::clothing

#endif  // FITBASE_CLOTHING_SIZE_ADVICE_H_
