#ifndef FITBASE_CORE_LOG_LINE_H_
#define FITBASE_CORE_LOG_LINE_H_

#include <cstdint>
#include <string>

#include "absl/strings/string_view.h"

namespace fitbase::core {

// One structured log line in logfmt, written to stderr whole when the LogLine is destroyed:
//   ts=2026-11-21T10:00:00.123Z event=task_leased build=build-000001 task=M/007 worker=w1
// Servers log events (not prose) so that logs of many workers can be filtered by build, task
// or key. Values with spaces, quotes or '=' are quoted. Lines from several threads never
// interleave.
class LogLine {
 public:
  explicit LogLine(absl::string_view event);
  ~LogLine();
  LogLine(const LogLine&) = delete;
  LogLine& operator=(const LogLine&) = delete;

  LogLine& Add(absl::string_view key, absl::string_view value);
  LogLine& Add(absl::string_view key, const char* value);
  LogLine& Add(absl::string_view key, int64_t value);
  LogLine& Add(absl::string_view key, uint64_t value);
  LogLine& Add(absl::string_view key, int value);
  LogLine& Add(absl::string_view key, uint32_t value);
  LogLine& Add(absl::string_view key, double value);

  // The line as it will be written, without the newline.
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

}  // namespace fitbase::core

#endif  // FITBASE_CORE_LOG_LINE_H_
