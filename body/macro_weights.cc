#include "body/macro_weights.h"

#include <algorithm>

#include "absl/strings/str_cat.h"

namespace fitbase::body {
namespace {

// Weights of every macro level for one set of parameters.
struct MacroLevels {
  std::array<Level, 3> ethnic;
  std::array<Level, 2> gender;
  std::array<Level, 2> age;
  std::array<Level, 3> muscle;
  std::array<Level, 3> weight;
  std::array<Level, 2> height;
  std::array<Level, 2> proportions;
  std::array<Level, 3> cup;
  std::array<Level, 3> firmness;
};

MacroLevels LevelsOf(const BodyParams& p) {
  const double h = p.height;
  const double r = p.proportions;
  return MacroLevels{
      .ethnic = {{{"african", p.african}, {"asian", p.asian}, {"caucasian", p.caucasian}}},
      .gender = GenderLevels(p.gender),
      .age = AgeLevels(AgeValueFromYears(p.age_years)),
      .muscle = ThreeLevels(p.muscle, kMuscleLevels),
      .weight = ThreeLevels(p.weight, kWeightLevels),
      .height = {{{"minheight", std::max(0.0, 1 - 2 * h)}, {"maxheight", std::max(0.0, 2 * h - 1)}}},
      .proportions = {{{"uncommonproportions", std::max(0.0, 1 - 2 * r)},
                       {"idealproportions", std::max(0.0, 2 * r - 1)}}},
      .cup = ThreeLevels(p.breast_size, kCupLevels),
      .firmness = ThreeLevels(p.breast_firmness, kFirmnessLevels),
  };
}

// Calls emit(path, weight) for every macro target, including those of weight zero, so that
// AllTargetPaths() shares this one enumeration.
template <typename Emit>
void ForEachMacroTarget(const MacroLevels& l, Emit emit) {
  for (const Level& g : l.gender) {
    for (const Level& a : l.age) {
      for (const Level& e : l.ethnic) {
        emit(absl::StrCat("macrodetails/", e.name, "-", g.name, "-", a.name, ".target"),
             e.weight * g.weight * a.weight);
      }
      for (const Level& m : l.muscle) {
        for (const Level& w : l.weight) {
          const std::string body = absl::StrCat(g.name, "-", a.name, "-", m.name, "-", w.name);
          const double gamw = g.weight * a.weight * m.weight * w.weight;
          emit(absl::StrCat("macrodetails/universal-", body, ".target"), gamw);
          for (const Level& h : l.height) {
            emit(absl::StrCat("macrodetails/height/", body, "-", h.name, ".target"),
                 gamw * h.weight);
          }
          for (const Level& p : l.proportions) {
            emit(absl::StrCat("macrodetails/proportions/", body, "-", p.name, ".target"),
                 gamw * p.weight);
          }
          // MakeHuman ships breast targets for the female level only, and none for an average
          // cup of average firmness: that combination is the base shape itself.
          if (g.name != "female") continue;
          for (const Level& c : l.cup) {
            for (const Level& f : l.firmness) {
              if (c.name == "averagecup" && f.name == "averagefirmness") continue;
              emit(absl::StrCat("breast/", body, "-", c.name, "-", f.name, ".target"),
                   gamw * c.weight * f.weight);
            }
          }
        }
      }
    }
  }
}

}  // namespace

std::array<Level, 3> ThreeLevels(double v, const LevelNames& names) {
  const double max_level = std::max(0.0, 2 * v - 1);
  const double min_level = std::max(0.0, 1 - 2 * v);
  return {{{names[0], min_level}, {names[1], 1 - min_level - max_level}, {names[2], max_level}}};
}

std::array<Level, 2> AgeLevels(double age_value) {
  const double old_level = 2 * (age_value - 0.5);
  return {{{"young", 1 - old_level}, {"old", old_level}}};
}

std::array<Level, 2> GenderLevels(double gender) {
  return {{{"female", 1 - gender}, {"male", gender}}};
}

std::vector<TargetWeight> ComputeTargetWeights(const BodyParams& params) {
  std::vector<TargetWeight> weights;
  ForEachMacroTarget(LevelsOf(params), [&](std::string path, double w) {
    if (w != 0.0) weights.push_back({std::move(path), w});
  });
  for (const auto& [name, value] : params.modifiers) {
    const LocalModifier* modifier = FindLocalModifier(name);
    if (value > 0) weights.push_back({std::string(modifier->increase_target), value});
    if (value < 0) weights.push_back({std::string(modifier->decrease_target), -value});
  }
  return weights;
}

std::vector<std::string> AllTargetPaths() {
  std::vector<std::string> paths;
  ForEachMacroTarget(LevelsOf(BodyParams{}), [&](std::string path, double) { paths.push_back(std::move(path)); });
  for (const LocalModifier& m : LocalModifiers()) {
    paths.emplace_back(m.decrease_target);
    paths.emplace_back(m.increase_target);
  }
  return paths;
}

}  // namespace fitbase::body
