#ifndef FITBASE_BODY_MACRO_WEIGHTS_H_
#define FITBASE_BODY_MACRO_WEIGHTS_H_

#include <array>
#include <string>
#include "absl/strings/string_view.h"
#include <vector>

#include "body/body_params.h"

namespace fitbase::body {

// A named level of a macro parameter and its weight, e.g. {"maxweight", 0.4}.
struct Level {
  absl::string_view name;
  double weight;
};

// The names of a three-level parameter, as in MakeHuman's file names: {min, average, max}.
using LevelNames = std::array<absl::string_view, 3>;
inline constexpr LevelNames kMuscleLevels = {"minmuscle", "averagemuscle", "maxmuscle"};
inline constexpr LevelNames kWeightLevels = {"minweight", "averageweight", "maxweight"};
inline constexpr LevelNames kCupLevels = {"mincup", "averagecup", "maxcup"};
inline constexpr LevelNames kFirmnessLevels = {"minfirmness", "averagefirmness", "maxfirmness"};

// MakeHuman's level rules (data/makehuman/README.md), for a value v in [0, 1]:
// min = max(0, 1 - 2v), max = max(0, 2v - 1), average = 1 - min - max.
std::array<Level, 3> ThreeLevels(double v, const LevelNames& names);
// young = 1 - 2(a - 0.5), old = 2(a - 0.5), for a in [0.5, 1].
std::array<Level, 2> AgeLevels(double age_value);
// female = 1 - g, male = g.
std::array<Level, 2> GenderLevels(double gender);

// A target file (path relative to targets/) and its weight in an avatar.
struct TargetWeight {
  std::string path;
  double weight;
};

// Every target with a non-zero weight for `params` (which must pass ValidateBodyParams):
// the macro targets (ethnic, universal, height, proportions, breast cup and firmness) and the
// one-sided local modifiers. A body is base + sum(weight * target).
std::vector<TargetWeight> ComputeTargetWeights(const BodyParams& params);

// Every target file that some valid parameters give a non-zero weight; a body model loads these.
std::vector<std::string> AllTargetPaths();

}  // namespace fitbase::body

#endif  // FITBASE_BODY_MACRO_WEIGHTS_H_
