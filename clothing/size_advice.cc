#include "clothing/size_advice.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"

namespace fitbase::clothing {
namespace {

constexpr std::array<absl::string_view, kFitRegionCount> kRegionNames = {
    "bust", "waist", "hip", "thigh", "upper_arm", "garment_length", "sleeve_length"};
constexpr std::array<absl::string_view, 4> kTypeNames = {"knit", "fitted", "shirt", "jacket"};

// By type, then girth region (bust, waist, hip, thigh, upper arm): {tight below, regular
// from, loose above}, cm. The regular bands are pattern-making's design ease at the bust (a
// fitted bodice +4-6, a shirt +6-10, a tailored jacket +8-12, knits 0 or negative, widened by
// a few cm because a grading step adds about 4 cm), and the usual smaller ease at the limbs.
constexpr EaseBand kBands[4][5] = {
    {{-10, -3, 4}, {-10, -3, 4}, {-10, -3, 4}, {-6, -2, 3}, {-4, -1.5, 2.5}},
    {{0, 4, 8}, {0, 2, 6}, {0, 3, 7}, {0, 2, 6}, {1, 3, 6}},
    {{2, 6, 12}, {2, 6, 14}, {2, 5, 12}, {2, 4, 9}, {2, 4, 9}},
    {{4, 8, 14}, {4, 8, 16}, {4, 6, 12}, {2, 4, 9}, {3, 5, 10}},
};

// Sentence text: "upper arm", "sleeve length".
std::string Spoken(FitRegion region) {
  std::string name(FitRegionName(region));
  std::replace(name.begin(), name.end(), '_', ' ');
  return name;
}

std::string SignedCm(double cm) {
  // U+2212 minus: the sign a shopper reads.
  return cm < 0 ? absl::StrFormat("\u2212%.1f cm", -cm) : absl::StrFormat("+%.1f cm", cm);
}

double RegionPenalty(GarmentType type, const RegionFitValue& value) {
  if (!IsGirth(value.region)) {
    const double off = std::abs(value.ease_cm - value.design_ease_cm) - kLengthToleranceCm;
    return 0.25 * std::max(0.0, off);
  }
  const EaseBand band = GirthEaseBand(type, value.region);
  return std::max(0.0, band.regular_from - value.ease_cm) +
         3 * std::max(0.0, band.tight_below - value.ease_cm) +
         std::max(0.0, value.ease_cm - band.loose_above);
}

// How far the size sits from the middle of its regular bands, cm: breaks ties between sizes
// that are regular everywhere.
double OffCentre(GarmentType type, std::span<const RegionFitValue> values) {
  double sum = 0;
  for (const RegionFitValue& value : values) {
    if (!IsGirth(value.region)) continue;
    const EaseBand band = GirthEaseBand(type, value.region);
    sum += std::abs(value.ease_cm - (band.regular_from + band.loose_above) / 2);
  }
  return sum;
}

std::string Describe(const RegionFitValue& value) {
  return absl::StrCat(Spoken(value.region), " (", SignedCm(value.ease_cm), ")");
}

}  // namespace

absl::string_view FitRegionName(FitRegion region) { return kRegionNames[static_cast<int>(region)]; }

bool IsGirth(FitRegion region) {
  return region != FitRegion::kGarmentLength && region != FitRegion::kSleeveLength;
}

absl::string_view GarmentTypeName(GarmentType type) { return kTypeNames[static_cast<int>(type)]; }

absl::StatusOr<GarmentType> ParseGarmentType(absl::string_view name) {
  for (size_t i = 0; i < kTypeNames.size(); ++i) {
    if (kTypeNames[i] == name) return static_cast<GarmentType>(i);
  }
  return absl::InvalidArgumentError(absl::StrCat("unknown garment type '", name,
                                                 "'; known: ", absl::StrJoin(kTypeNames, ", ")));
}

absl::string_view VerdictName(Verdict verdict) {
  constexpr std::array<absl::string_view, 6> kNames = {"tight", "fitted", "regular",
                                                       "loose", "short",  "long"};
  return kNames[static_cast<int>(verdict)];
}

EaseBand GirthEaseBand(GarmentType type, FitRegion region) {
  return kBands[static_cast<int>(type)][std::min(static_cast<int>(region), 4)];
}

void JudgeRegions(GarmentType type, std::span<RegionFitValue> values) {
  for (RegionFitValue& value : values) {
    if (!IsGirth(value.region)) {
      const double off = value.ease_cm - value.design_ease_cm;
      value.verdict = off < -kLengthToleranceCm  ? Verdict::kShort
                      : off > kLengthToleranceCm ? Verdict::kLong
                                                 : Verdict::kRegular;
      continue;
    }
    const EaseBand band = GirthEaseBand(type, value.region);
    value.verdict = value.ease_cm < band.tight_below    ? Verdict::kTight
                    : value.ease_cm < band.regular_from ? Verdict::kFitted
                    : value.ease_cm > band.loose_above  ? Verdict::kLoose
                                                        : Verdict::kRegular;
  }
}

double SizePenalty(GarmentType type, std::span<const RegionFitValue> values) {
  double penalty = 0;
  for (const RegionFitValue& value : values) penalty += RegionPenalty(type, value);
  return penalty;
}

SizeRecommendation RecommendSize(GarmentType type, std::span<const std::string> names,
                                 std::span<const std::vector<RegionFitValue>> sizes) {
  SizeRecommendation out;
  std::vector<double> penalty(sizes.size());
  for (size_t i = 0; i < sizes.size(); ++i) {
    penalty[i] = SizePenalty(type, sizes[i]);
    // The size's verdict and summary: its regions off the regular band, worst first.
    std::vector<const RegionFitValue*> off;
    for (const RegionFitValue& value : sizes[i]) {
      if (value.verdict != Verdict::kRegular) off.push_back(&value);
    }
    std::stable_sort(off.begin(), off.end(), [&](const auto* a, const auto* b) {
      return RegionPenalty(type, *a) > RegionPenalty(type, *b);
    });
    out.overall.push_back(off.empty() ? Verdict::kRegular : off.front()->verdict);
    if (off.empty()) {
      out.summaries.push_back(absl::StrCat(names[i], ": regular fit"));
      continue;
    }
    // Regions of one verdict are said together: "tight at the bust (-2.1 cm), waist (-0.4 cm)".
    const Verdict worst = off.front()->verdict;
    std::vector<std::string> where;
    for (const RegionFitValue* value : off) {
      if (value->verdict == worst && where.size() < 3) where.push_back(Describe(*value));
    }
    std::vector<std::string> parts = {
        absl::StrCat(VerdictName(worst), " at the ", absl::StrJoin(where, ", "))};
    for (const RegionFitValue* value : off) {
      if (value->verdict != worst && parts.size() < 3) {
        parts.push_back(absl::StrCat(VerdictName(value->verdict), " at the ", Describe(*value)));
      }
    }
    out.summaries.push_back(absl::StrCat(names[i], ": ", absl::StrJoin(parts, "; ")));
  }
  if (sizes.empty()) return out;

  double best_key = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < sizes.size(); ++i) {
    // A size without penalty ranks by its distance from the bands' middles, which stays below
    // any penalty's scale only as a tie-break.
    const double key = penalty[i] + 1e-3 * OffCentre(type, sizes[i]);
    if (key < best_key) {
      best_key = key;
      out.best = static_cast<int>(i);
    }
  }
  double next = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < sizes.size(); ++i) {
    if (static_cast<int>(i) != out.best) next = std::min(next, penalty[i]);
  }
  const double margin = std::isfinite(next) ? next - penalty[out.best] : 10.0;
  out.confidence = 1 - 0.5 * std::exp(-margin / 2.0);

  const std::vector<RegionFitValue>& best = sizes[out.best];
  std::vector<std::string> regular;
  for (const RegionFitValue& value : best) {
    if (IsGirth(value.region) && value.verdict == Verdict::kRegular) {
      regular.push_back(Describe(value));
    }
  }
  if (penalty[out.best] == 0) {
    out.reasons.push_back(absl::StrCat(names[out.best], " has the ease a ",
                                       GarmentTypeName(type), " is cut with at the ",
                                       absl::StrJoin(regular, ", ")));
  } else {
    out.reasons.push_back(absl::StrCat(out.summaries[out.best], ", the closest of the sizes"));
  }
  for (int neighbour : {out.best - 1, out.best + 1}) {
    if (neighbour >= 0 && neighbour < static_cast<int>(sizes.size())) {
      out.reasons.push_back(out.summaries[neighbour]);
    }
  }
  return out;
}

}  // namespace fitbase::clothing
