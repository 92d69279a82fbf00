#include "proto/avatar_params_codec.h"

#include "core/status_macros.h"

namespace fitbase::proto {

absl::StatusOr<body::BodyParams> BodyParamsFromProto(const v1::AvatarParams& m) {
  body::BodyParams p;
  if (m.has_gender()) p.gender = m.gender();
  if (m.has_age_years()) p.age_years = m.age_years();
  if (m.has_muscle()) p.muscle = m.muscle();
  if (m.has_weight()) p.weight = m.weight();
  if (m.has_height()) p.height = m.height();
  if (m.has_proportions()) p.proportions = m.proportions();
  if (m.has_african()) p.african = m.african();
  if (m.has_asian()) p.asian = m.asian();
  if (m.has_caucasian()) p.caucasian = m.caucasian();
  if (m.has_breast_size()) p.breast_size = m.breast_size();
  if (m.has_breast_firmness()) p.breast_firmness = m.breast_firmness();
  for (const auto& [name, value] : m.modifiers()) p.modifiers[name] = value;
  RETURN_IF_ERROR(body::ValidateBodyParams(p));
  return p;
}

v1::AvatarParams BodyParamsToProto(const body::BodyParams& p) {
  v1::AvatarParams m;
  m.set_gender(p.gender);
  m.set_age_years(p.age_years);
  m.set_muscle(p.muscle);
  m.set_weight(p.weight);
  m.set_height(p.height);
  m.set_proportions(p.proportions);
  m.set_african(p.african);
  m.set_asian(p.asian);
  m.set_caucasian(p.caucasian);
  m.set_breast_size(p.breast_size);
  m.set_breast_firmness(p.breast_firmness);
  for (const auto& [name, value] : p.modifiers) (*m.mutable_modifiers())[name] = value;
  return m;
}

}  // namespace fitbase::proto
