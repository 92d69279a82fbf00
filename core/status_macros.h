#ifndef FITBASE_CORE_STATUS_MACROS_H_
#define FITBASE_CORE_STATUS_MACROS_H_

#include "absl/status/status.h"
#include "absl/status/statusor.h"

// Early-return helpers for absl::Status / absl::StatusOr, as in Draco and Abseil-based code.
#define FITBASE_CONCAT_INNER_(a, b) a##b
#define FITBASE_CONCAT_(a, b) FITBASE_CONCAT_INNER_(a, b)

#define RETURN_IF_ERROR(expr)                      \
  do {                                             \
    ::absl::Status fitbase_status_ = (expr);       \
    if (!fitbase_status_.ok()) return fitbase_status_; \
  } while (0)

#define ASSIGN_OR_RETURN_IMPL_(statusor, lhs, rexpr) \
  auto statusor = (rexpr);                           \
  if (!statusor.ok()) return statusor.status();      \
  lhs = std::move(statusor).value()

#define ASSIGN_OR_RETURN(lhs, rexpr) \
  ASSIGN_OR_RETURN_IMPL_(FITBASE_CONCAT_(fitbase_statusor_, __LINE__), lhs, rexpr)

#endif  // FITBASE_CORE_STATUS_MACROS_H_
