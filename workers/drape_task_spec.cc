#include "workers/drape_task_spec.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "body/body_model.h"
#include "core/status_macros.h"

namespace fitbase::workers {
namespace {

// Bounds that keep a malformed spec from making a worker run for hours or allocate without
// limit; real schedules are a few dozen steps.
constexpr uint32_t kMaxNewtonIterations = 1000;
constexpr uint32_t kMaxScheduleSteps = 100000;

absl::Status CheckPositive(const char* name, double value) {
  if (!std::isfinite(value) || value <= 0) {
    return absl::InvalidArgumentError(absl::StrCat("drape setting ", name, " = ", value,
                                                   " must be finite and positive"));
  }
  return absl::OkStatus();
}

absl::Status CheckNonNegative(const char* name, double value) {
  if (!std::isfinite(value) || value < 0) {
    return absl::InvalidArgumentError(absl::StrCat("drape setting ", name, " = ", value,
                                                   " must be finite and not negative"));
  }
  return absl::OkStatus();
}

absl::Status CheckShare(const char* name, double value) {
  if (!(value >= 0 && value <= 1)) {
    return absl::InvalidArgumentError(
        absl::StrCat("drape setting ", name, " = ", value, " must be a share in [0, 1]"));
  }
  return absl::OkStatus();
}

absl::Status CheckCount(const char* name, uint32_t value, uint32_t low, uint32_t high) {
  if (value < low || value > high) {
    return absl::InvalidArgumentError(absl::StrCat("drape setting ", name, " = ", value,
                                                   " is outside [", low, ", ", high, "]"));
  }
  return absl::OkStatus();
}

}  // namespace

v1::DrapeSettings DrapeSettingsToProto(const ClothSettings& s, const DrapeSchedule& schedule) {
  v1::DrapeSettings proto;
  proto.set_step_seconds(s.step_seconds);
  proto.set_newton_iterations(static_cast<uint32_t>(s.newton_iterations));
  proto.set_newton_tolerance(s.newton_tolerance);
  proto.set_path_newton_iterations(static_cast<uint32_t>(s.path_newton_iterations));
  proto.set_gravity(s.gravity);
  proto.set_areal_density(s.areal_density);
  proto.set_stretch_stiffness(s.stretch_stiffness);
  proto.set_compression_stiffness(s.compression_stiffness);
  proto.set_area_floor(s.area_floor);
  proto.set_bending_rigidity(s.bending_rigidity);
  proto.set_anchor_stiffness(s.anchor_stiffness);
  proto.set_skin_tie(s.skin_tie);
  proto.set_friction(s.friction);
  proto.set_cuff_friction(s.cuff_friction);
  proto.set_waistband_grip(s.waistband_grip);
  proto.set_waistband_stiffness(s.waistband_stiffness);
  proto.set_waistband_anchor_stiffness(s.waistband_anchor_stiffness);
  proto.set_waistband_on_rise(s.waistband_on_rise);
  proto.set_factorization(s.factorization == Factorization::kSimplicialLdlt
                              ? v1::FACTORIZATION_SIMPLICIAL_LDLT
                              : v1::FACTORIZATION_SUPERNODAL_CHOLMOD);
  proto.set_contact_stiffness(s.contact_stiffness);
  proto.set_collision_offset(s.collision_offset);
  proto.set_collision_search(s.collision_search);
  proto.set_homotopy_steps(static_cast<uint32_t>(schedule.homotopy_steps));
  proto.set_relax_steps(static_cast<uint32_t>(schedule.relax_steps));
  return proto;
}

absl::Status DrapeSettingsFromProto(const v1::DrapeSettings& p, ClothSettings* settings,
                                    DrapeSchedule* schedule) {
  RETURN_IF_ERROR(CheckPositive("step_seconds", p.step_seconds()));
  RETURN_IF_ERROR(
      CheckCount("newton_iterations", p.newton_iterations(), 1, kMaxNewtonIterations));
  RETURN_IF_ERROR(CheckNonNegative("newton_tolerance", p.newton_tolerance()));
  RETURN_IF_ERROR(CheckCount("path_newton_iterations", p.path_newton_iterations(), 1,
                             kMaxNewtonIterations));
  RETURN_IF_ERROR(CheckNonNegative("gravity", p.gravity()));
  RETURN_IF_ERROR(CheckPositive("areal_density", p.areal_density()));
  RETURN_IF_ERROR(CheckPositive("stretch_stiffness", p.stretch_stiffness()));
  RETURN_IF_ERROR(CheckPositive("compression_stiffness", p.compression_stiffness()));
  RETURN_IF_ERROR(CheckShare("area_floor", p.area_floor()));
  RETURN_IF_ERROR(CheckNonNegative("bending_rigidity", p.bending_rigidity()));
  RETURN_IF_ERROR(CheckNonNegative("anchor_stiffness", p.anchor_stiffness()));
  if (absl::Status tie = CheckSkinTie(p.skin_tie(), "skin_tie"); !tie.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("drape setting ", tie.message()));
  }
  if (absl::Status friction = CheckFriction(p.friction(), "friction"); !friction.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("drape setting ", friction.message()));
  }
  if (absl::Status friction = CheckFriction(p.cuff_friction(), "cuff_friction"); !friction.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("drape setting ", friction.message()));
  }
  RETURN_IF_ERROR(CheckShare("waistband_grip", p.waistband_grip()));
  RETURN_IF_ERROR(CheckNonNegative("waistband_stiffness", p.waistband_stiffness()));
  RETURN_IF_ERROR(
      CheckNonNegative("waistband_anchor_stiffness", p.waistband_anchor_stiffness()));
  if (!v1::Factorization_IsValid(p.factorization())) {
    return absl::InvalidArgumentError(
        absl::StrCat("drape setting factorization = ", p.factorization(), " is not known"));
  }
  RETURN_IF_ERROR(CheckPositive("contact_stiffness", p.contact_stiffness()));
  RETURN_IF_ERROR(CheckNonNegative("collision_offset", p.collision_offset()));
  RETURN_IF_ERROR(CheckPositive("collision_search", p.collision_search()));
  RETURN_IF_ERROR(CheckCount("homotopy_steps", p.homotopy_steps(), 1, kMaxScheduleSteps));
  RETURN_IF_ERROR(CheckCount("relax_steps", p.relax_steps(), 0, kMaxScheduleSteps));
  *settings = ClothSettings{.step_seconds = p.step_seconds(),
                            .newton_iterations = static_cast<int>(p.newton_iterations()),
                            .newton_tolerance = p.newton_tolerance(),
                            .path_newton_iterations =
                                static_cast<int>(p.path_newton_iterations()),
                            .gravity = p.gravity(),
                            .areal_density = p.areal_density(),
                            .stretch_stiffness = p.stretch_stiffness(),
                            .compression_stiffness = p.compression_stiffness(),
                            .area_floor = p.area_floor(),
                            .bending_rigidity = p.bending_rigidity(),
                            .anchor_stiffness = p.anchor_stiffness(),
                            .skin_tie = p.skin_tie(),
                            .friction = p.friction(),
                            .cuff_friction = p.cuff_friction(),
                            .waistband_grip = p.waistband_grip(),
                            .waistband_stiffness = p.waistband_stiffness(),
                            .waistband_anchor_stiffness = p.waistband_anchor_stiffness(),
                            .waistband_on_rise = p.waistband_on_rise(),
                            .contact_stiffness = p.contact_stiffness(),
                            .collision_offset = p.collision_offset(),
                            .collision_search = p.collision_search(),
                            .factorization =
                                p.factorization() == v1::FACTORIZATION_SUPERNODAL_CHOLMOD
                                    ? Factorization::kSupernodalCholmod
                                    : Factorization::kSimplicialLdlt};
  *schedule = DrapeSchedule{.homotopy_steps = static_cast<int>(p.homotopy_steps()),
                            .relax_steps = static_cast<int>(p.relax_steps())};
  return absl::OkStatus();
}

v1::DrapeTaskSpec DrapeTaskToSpec(const DrapeTask& task) {
  v1::DrapeTaskSpec spec;
  spec.set_key(task.key);
  *spec.mutable_garment() = *task.garment;
  spec.set_size(task.size);
  auto* body = spec.mutable_body();
  body->Reserve(static_cast<int>(task.body.size()));
  for (double value : task.body.reshaped<Eigen::RowMajor>()) {
    body->AddAlreadyReserved(static_cast<float>(value));
  }
  *spec.mutable_settings() = DrapeSettingsToProto(task.settings, task.schedule);
  return spec;
}

absl::StatusOr<DrapeTask> DrapeTaskFromSpec(const v1::DrapeTaskSpec& spec) {
  if (spec.body_size() != 3 * body::kBodyVertexCount) {
    return absl::InvalidArgumentError(absl::StrCat("task ", spec.key(), ": the body has ",
                                                   spec.body_size(), " coordinates; expected ",
                                                   3 * body::kBodyVertexCount));
  }
  const core::Positions body =
      Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
          spec.body().data(), body::kBodyVertexCount, 3)
          .cast<double>();
  if (!body.allFinite()) {
    return absl::InvalidArgumentError(absl::StrCat("task ", spec.key(), ": non-finite body"));
  }
  ClothSettings settings;
  DrapeSchedule schedule;
  RETURN_IF_ERROR(DrapeSettingsFromProto(spec.settings(), &settings, &schedule));
  DrapeTask task = MakeDrapeTask(spec.garment(), spec.size(), body, settings, schedule);
  if (task.key != spec.key()) {
    return absl::InvalidArgumentError(absl::StrCat("task ", spec.key(),
                                                   ": its content hashes to ", task.key));
  }
  return task;
}

}  // namespace fitbase::workers
