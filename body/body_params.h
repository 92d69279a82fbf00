#ifndef FITBASE_BODY_BODY_PARAMS_H_
#define FITBASE_BODY_BODY_PARAMS_H_

#include <map>
#include <span>
#include <string>
#include "absl/strings/string_view.h"

#include "absl/status/status.h"

namespace fitbase::body {

inline constexpr double kMinAgeYears = 25.0;
inline constexpr double kMaxAgeYears = 90.0;

// The parameters of one MakeHuman adult, with MakeHuman's defaults (its "default human").
// Macro values are in [0, 1]; see data/makehuman/README.md for how they weight the targets.
struct BodyParams {
  double gender = 0.5;        // 0 = female, 1 = male.
  double age_years = 25.0;   // MakeHuman default a = 0.5, i.e. 25 years.
  double muscle = 0.5;
  double weight = 0.5;
  double height = 0.5;        // 0.5 is neutral.
  double proportions = 0.5;   // 0.5 is neutral.
  double african = 1.0 / 3.0;  // Ethnic shares: non-negative, summing to 1.
  double asian = 1.0 / 3.0;
  double caucasian = 1.0 / 3.0;
  double breast_size = 0.5;      // Cup level; 0.5 is average.
  double breast_firmness = 0.5;  // 0.5 is average.
  // Local one-sided modifiers by MakeHuman name (see kLocalModifiers), each in [-1, 1].
  std::map<std::string, double, std::less<>> modifiers;

  bool operator==(const BodyParams&) const = default;
};

// MakeHuman's age value a in [0.5, 1] for an adult age in years (0.5 = 25, 1 = 90).
double AgeValueFromYears(double age_years);

// Checks ranges, ethnic shares (sum 1 within 1e-6), finiteness and modifier names; the error
// names the offending parameter.
absl::Status ValidateBodyParams(const BodyParams& params);

// A one-sided local modifier: value v < 0 applies `decrease_target` with weight -v, v > 0
// applies `increase_target` with weight v. Paths are relative to the data's targets/ folder.
struct LocalModifier {
  absl::string_view name;  // MakeHuman's name, "group/target-min|max".
  absl::string_view decrease_target;
  absl::string_view increase_target;
};

// The local modifiers of the groups measure, torso, hip, stomach, buttocks and breast, in the
// order of MakeHuman's modifiers/*.json.
std::span<const LocalModifier> LocalModifiers();

// The modifier named `name`, or nullptr.
const LocalModifier* FindLocalModifier(absl::string_view name);

}  // namespace fitbase::body

#endif  // FITBASE_BODY_BODY_PARAMS_H_
