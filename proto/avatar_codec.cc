#include "proto/avatar_codec.h"

#include <cmath>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "body/body_model.h"
#include "core/status_macros.h"
#include "proto/avatar_params_codec.h"
#include "proto/draco_codec.h"

namespace fitbase::proto {
namespace {

// Any adult a shop may dress, with a wide margin; outside it the unit is wrong, not the body.
constexpr double kMinHeightM = 0.5;
constexpr double kMaxHeightM = 2.5;
// MakeHuman's origin lies near the hips: a bounding box centred farther away is a translated
// body (e.g. exported with its feet on the ground), which the avatar bases would misread as
// shape.
constexpr double kMaxCentreOffsetM = 0.5;
constexpr double kMinCircumferenceM = 0.2;
constexpr double kMaxCircumferenceM = 3.0;
constexpr double kMinInseamM = 0.2;
constexpr double kMaxInseamM = 1.5;

// "; it looks like centimeters" when `value` scaled from a common unit to meters lands in
// [low, high], else "".
std::string UnitHint(double value, double low, double high) {
  struct Unit {
    double meters;
    const char* name;
  };
  for (const Unit& unit : {Unit{0.1, "decimeters (MakeHuman's own unit)"},
                           Unit{0.01, "centimeters"}, Unit{0.001, "millimeters"}}) {
    const double meters = value * unit.meters;
    if (meters >= low && meters <= high) return absl::StrCat("; it looks like ", unit.name);
  }
  return "";
}

absl::Status ValidateBody(const core::Positions& positions) {
  if (positions.rows() != body::kBodyVertexCount) {
    return absl::InvalidArgumentError(absl::StrCat("avatar has ", positions.rows(),
                                                   " vertices; a ", body::kBodyTopologyId,
                                                   " avatar has ", body::kBodyVertexCount));
  }
  for (Eigen::Index v = 0; v < positions.rows(); ++v) {
    if (!positions.row(v).allFinite()) {
      return absl::InvalidArgumentError(
          absl::StrCat("avatar vertex ", v, " has a non-finite coordinate"));
    }
  }
  const Eigen::RowVector3d low = positions.colwise().minCoeff();
  const Eigen::RowVector3d high = positions.colwise().maxCoeff();
  const double height = high.y() - low.y();
  if (height < kMinHeightM || height > kMaxHeightM) {
    return absl::InvalidArgumentError(absl::StrCat(
        "avatar is ", height, " units tall along +y; positions are meters with +y up (",
        kMinHeightM, " to ", kMaxHeightM, " m tall)", UnitHint(height, kMinHeightM, kMaxHeightM)));
  }
  const Eigen::RowVector3d centre = 0.5 * (low + high);
  if (centre.cwiseAbs().maxCoeff() > kMaxCentreOffsetM) {
    return absl::InvalidArgumentError(absl::StrCat(
        "avatar's bounding box is centred at (", centre.x(), ", ", centre.y(), ", ", centre.z(),
        ") m; positions are in MakeHuman's model frame, origin near the hips (not moved, e.g. "
        "not with the feet on the ground)"));
  }
  return absl::OkStatus();
}

absl::Status CheckMeasurement(bool present, double value, absl::string_view name, double low,
                              double high) {
  if (!present || (value >= low && value <= high)) return absl::OkStatus();
  return absl::InvalidArgumentError(absl::StrCat("avatar measurements.", name, " is ", value,
                                                 "; expected ", low, " to ", high, " (meters)",
                                                 UnitHint(value, low, high)));
}

absl::Status ValidateMeasurements(const v1::AvatarMeasurements& m) {
  RETURN_IF_ERROR(
      CheckMeasurement(m.has_height_m(), m.height_m(), "height_m", kMinHeightM, kMaxHeightM));
  RETURN_IF_ERROR(CheckMeasurement(m.has_chest_circumference_m(), m.chest_circumference_m(),
                                   "chest_circumference_m", kMinCircumferenceM,
                                   kMaxCircumferenceM));
  RETURN_IF_ERROR(CheckMeasurement(m.has_waist_circumference_m(), m.waist_circumference_m(),
                                   "waist_circumference_m", kMinCircumferenceM,
                                   kMaxCircumferenceM));
  RETURN_IF_ERROR(CheckMeasurement(m.has_hip_circumference_m(), m.hip_circumference_m(),
                                   "hip_circumference_m", kMinCircumferenceM,
                                   kMaxCircumferenceM));
  return CheckMeasurement(m.has_inseam_m(), m.inseam_m(), "inseam_m", kMinInseamM, kMaxInseamM);
}

absl::Status ValidateParams(const v1::AvatarParams& params) {
  const absl::Status status = BodyParamsFromProto(params).status();
  if (status.ok()) return status;
  return absl::Status(status.code(), absl::StrCat("avatar params: ", status.message()));
}

}  // namespace

absl::StatusOr<core::Positions> AvatarPositions(const v1::Avatar& avatar) {
  if (avatar.format_version() != kAvatarFormatVersion) {
    return absl::InvalidArgumentError(
        absl::StrCat("avatar format_version is ", avatar.format_version(),
                     "; this reader supports format_version ", kAvatarFormatVersion));
  }
  if (avatar.topology_id() != body::kBodyTopologyId) {
    return absl::InvalidArgumentError(absl::StrCat("avatar topology_id is \"",
                                                   avatar.topology_id(), "\"; expected \"",
                                                   body::kBodyTopologyId, "\""));
  }
  auto xyz = DecodePositions(avatar.positions(), body::kBodyVertexCount);
  if (!xyz.ok()) {
    return absl::Status(xyz.status().code(),
                        absl::StrCat("avatar positions: ", xyz.status().message()));
  }
  core::Positions positions(body::kBodyVertexCount, 3);
  for (Eigen::Index i = 0; i < positions.size(); ++i) positions.data()[i] = (*xyz)[i];
  RETURN_IF_ERROR(ValidateBody(positions));
  RETURN_IF_ERROR(ValidateMeasurements(avatar.measurements()));
  if (avatar.has_params()) RETURN_IF_ERROR(ValidateParams(avatar.params()));
  return positions;
}

absl::StatusOr<v1::Avatar> AvatarFromPositions(const core::Positions& positions, bool draco,
                                               const v1::AvatarParams* params) {
  RETURN_IF_ERROR(ValidateBody(positions));
  if (params != nullptr) RETURN_IF_ERROR(ValidateParams(*params));
  const std::vector<float> xyz(positions.data(), positions.data() + positions.size());
  v1::Avatar avatar;
  avatar.set_format_version(kAvatarFormatVersion);
  avatar.set_topology_id(std::string(body::kBodyTopologyId));
  if (draco) {
    ASSIGN_OR_RETURN(*avatar.mutable_positions(), EncodeDracoPositions(xyz));
  } else {
    *avatar.mutable_positions() = EncodeRawPositions(xyz);
  }
  if (params != nullptr) *avatar.mutable_params() = *params;
  return avatar;
}

}  // namespace fitbase::proto
