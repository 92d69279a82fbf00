#include "body/body_params.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"

namespace fitbase::body {
namespace {

constexpr LocalModifier kLocalModifiers[] = {
    {"measure/measure-neck-circ-decr|incr", "measure/measure-neck-circ-decr.target", "measure/measure-neck-circ-incr.target"},
    {"measure/measure-neck-height-decr|incr", "measure/measure-neck-height-decr.target", "measure/measure-neck-height-incr.target"},
    {"measure/measure-upperarm-circ-decr|incr", "measure/measure-upperarm-circ-decr.target", "measure/measure-upperarm-circ-incr.target"},
    {"measure/measure-upperarm-length-decr|incr", "measure/measure-upperarm-length-decr.target", "measure/measure-upperarm-length-incr.target"},
    {"measure/measure-lowerarm-length-decr|incr", "measure/measure-lowerarm-length-decr.target", "measure/measure-lowerarm-length-incr.target"},
    {"measure/measure-wrist-circ-decr|incr", "measure/measure-wrist-circ-decr.target", "measure/measure-wrist-circ-incr.target"},
    {"measure/measure-frontchest-dist-decr|incr", "measure/measure-frontchest-dist-decr.target", "measure/measure-frontchest-dist-incr.target"},
    {"measure/measure-bust-circ-decr|incr", "measure/measure-bust-circ-decr.target", "measure/measure-bust-circ-incr.target"},
    {"measure/measure-underbust-circ-decr|incr", "measure/measure-underbust-circ-decr.target", "measure/measure-underbust-circ-incr.target"},
    {"measure/measure-waist-circ-decr|incr", "measure/measure-waist-circ-decr.target", "measure/measure-waist-circ-incr.target"},
    {"measure/measure-napetowaist-dist-decr|incr", "measure/measure-napetowaist-dist-decr.target", "measure/measure-napetowaist-dist-incr.target"},
    {"measure/measure-waisttohip-dist-decr|incr", "measure/measure-waisttohip-dist-decr.target", "measure/measure-waisttohip-dist-incr.target"},
    {"measure/measure-shoulder-dist-decr|incr", "measure/measure-shoulder-dist-decr.target", "measure/measure-shoulder-dist-incr.target"},
    {"measure/measure-hips-circ-decr|incr", "measure/measure-hips-circ-decr.target", "measure/measure-hips-circ-incr.target"},
    {"measure/measure-upperleg-height-decr|incr", "measure/measure-upperleg-height-decr.target", "measure/measure-upperleg-height-incr.target"},
    {"measure/measure-thigh-circ-decr|incr", "measure/measure-thigh-circ-decr.target", "measure/measure-thigh-circ-incr.target"},
    {"measure/measure-lowerleg-height-decr|incr", "measure/measure-lowerleg-height-decr.target", "measure/measure-lowerleg-height-incr.target"},
    {"measure/measure-calf-circ-decr|incr", "measure/measure-calf-circ-decr.target", "measure/measure-calf-circ-incr.target"},
    {"measure/measure-knee-circ-decr|incr", "measure/measure-knee-circ-decr.target", "measure/measure-knee-circ-incr.target"},
    {"measure/measure-ankle-circ-decr|incr", "measure/measure-ankle-circ-decr.target", "measure/measure-ankle-circ-incr.target"},
    {"torso/torso-scale-depth-decr|incr", "torso/torso-scale-depth-decr.target", "torso/torso-scale-depth-incr.target"},
    {"torso/torso-scale-horiz-decr|incr", "torso/torso-scale-horiz-decr.target", "torso/torso-scale-horiz-incr.target"},
    {"torso/torso-scale-vert-decr|incr", "torso/torso-scale-vert-decr.target", "torso/torso-scale-vert-incr.target"},
    {"torso/torso-trans-in|out", "torso/torso-trans-in.target", "torso/torso-trans-out.target"},
    {"torso/torso-trans-down|up", "torso/torso-trans-down.target", "torso/torso-trans-up.target"},
    {"torso/torso-trans-backward|forward", "torso/torso-trans-backward.target", "torso/torso-trans-forward.target"},
    {"torso/torso-vshape-decr|incr", "torso/torso-vshape-decr.target", "torso/torso-vshape-incr.target"},
    {"torso/torso-muscle-dorsi-decr|incr", "torso/torso-muscle-dorsi-decr.target", "torso/torso-muscle-dorsi-incr.target"},
    {"torso/torso-muscle-pectoral-decr|incr", "torso/torso-muscle-pectoral-decr.target", "torso/torso-muscle-pectoral-incr.target"},
    {"hip/hip-scale-depth-decr|incr", "hip/hip-scale-depth-decr.target", "hip/hip-scale-depth-incr.target"},
    {"hip/hip-scale-horiz-decr|incr", "hip/hip-scale-horiz-decr.target", "hip/hip-scale-horiz-incr.target"},
    {"hip/hip-scale-vert-decr|incr", "hip/hip-scale-vert-decr.target", "hip/hip-scale-vert-incr.target"},
    {"hip/hip-trans-in|out", "hip/hip-trans-in.target", "hip/hip-trans-out.target"},
    {"hip/hip-trans-down|up", "hip/hip-trans-down.target", "hip/hip-trans-up.target"},
    {"hip/hip-trans-backward|forward", "hip/hip-trans-backward.target", "hip/hip-trans-forward.target"},
    {"hip/hip-waist-down|up", "hip/hip-waist-down.target", "hip/hip-waist-up.target"},
    {"stomach/stomach-navel-in|out", "stomach/stomach-navel-in.target", "stomach/stomach-navel-out.target"},
    {"stomach/stomach-tone-decr|incr", "stomach/stomach-tone-decr.target", "stomach/stomach-tone-incr.target"},
    {"stomach/stomach-pregnant-decr|incr", "stomach/stomach-pregnant-decr.target", "stomach/stomach-pregnant-incr.target"},
    {"stomach/stomach-navel-down|up", "stomach/stomach-navel-down.target", "stomach/stomach-navel-up.target"},
    {"buttocks/buttocks-volume-decr|incr", "buttocks/buttocks-volume-decr.target", "buttocks/buttocks-volume-incr.target"},
    {"breast/breast-trans-down|up", "breast/breast-trans-down.target", "breast/breast-trans-up.target"},
    {"breast/breast-dist-decr|incr", "breast/breast-dist-decr.target", "breast/breast-dist-incr.target"},
    {"breast/breast-point-decr|incr", "breast/breast-point-decr.target", "breast/breast-point-incr.target"},
    {"breast/breast-volume-vert-down|up", "breast/breast-volume-vert-down.target", "breast/breast-volume-vert-up.target"},
    {"breast/nipple-size-decr|incr", "breast/nipple-size-decr.target", "breast/nipple-size-incr.target"},
    {"breast/nipple-point-decr|incr", "breast/nipple-point-decr.target", "breast/nipple-point-incr.target"},
};

absl::Status CheckUnit(absl::string_view name, double value, double lo, double hi) {
  if (!std::isfinite(value) || value < lo || value > hi) {
    return absl::InvalidArgumentError(
        absl::StrCat("parameter '", name, "' is ", value, ", outside [", lo, ", ", hi, "]"));
  }
  return absl::OkStatus();
}

}  // namespace

double AgeValueFromYears(double age_years) {
  return 0.5 + 0.5 * (age_years - kMinAgeYears) / (kMaxAgeYears - kMinAgeYears);
}

absl::Status ValidateBodyParams(const BodyParams& p) {
  const std::array<std::pair<absl::string_view, double>, 10> unit = {{
      {"gender", p.gender},
      {"muscle", p.muscle},
      {"weight", p.weight},
      {"height", p.height},
      {"proportions", p.proportions},
      {"african", p.african},
      {"asian", p.asian},
      {"caucasian", p.caucasian},
      {"breast_size", p.breast_size},
      {"breast_firmness", p.breast_firmness},
  }};
  for (const auto& [name, value] : unit) {
    RETURN_IF_ERROR(CheckUnit(name, value, 0.0, 1.0));
  }
  RETURN_IF_ERROR(CheckUnit("age_years", p.age_years, kMinAgeYears, kMaxAgeYears));
  const double ethnic_sum = p.african + p.asian + p.caucasian;
  if (std::abs(ethnic_sum - 1.0) > 1e-6) {
    return absl::InvalidArgumentError(absl::StrCat(
        "ethnic shares african + asian + caucasian sum to ", ethnic_sum, ", not 1"));
  }
  for (const auto& [name, value] : p.modifiers) {
    if (FindLocalModifier(name) == nullptr) {
      return absl::InvalidArgumentError(absl::StrCat(
          "unknown modifier '", name, "' (expected a name like 'measure/measure-waist-circ-decr|incr')"));
    }
    RETURN_IF_ERROR(CheckUnit(name, value, -1.0, 1.0));
  }
  return absl::OkStatus();
}

std::span<const LocalModifier> LocalModifiers() { return kLocalModifiers; }

const LocalModifier* FindLocalModifier(absl::string_view name) {
  const auto* it = std::find_if(std::begin(kLocalModifiers), std::end(kLocalModifiers),
                                [name](const LocalModifier& m) { return m.name == name; });
  return it == std::end(kLocalModifiers) ? nullptr : it;
}

}  // namespace fitbase::body
