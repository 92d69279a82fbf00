#include "core/log_line.h"

#include <cstdio>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"

namespace fitbase::core {
namespace {

bool NeedsQuotes(absl::string_view value) {
  if (value.empty()) return true;
  for (char c : value) {
    if (c == ' ' || c == '"' || c == '=' || c == '\\' || c < 0x20) return true;
  }
  return false;
}

void AppendValue(std::string& out, absl::string_view value) {
  if (!NeedsQuotes(value)) {
    out.append(value.data(), value.size());
    return;
  }
  out.push_back('"');
  for (char c : value) {
    if (c == '"' || c == '\\') {
      out.push_back('\\');
      out.push_back(c);
    } else if (c == '\n') {
      out.append("\\n");
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out.push_back(' ');
    } else {
      out.push_back(c);
    }
  }
  out.push_back('"');
}

}  // namespace

LogLine::LogLine(absl::string_view event) {
  text_ = absl::StrCat("ts=", absl::FormatTime("%Y-%m-%dT%H:%M:%E3SZ", absl::Now(),
                                               absl::UTCTimeZone()));
  Add("event", event);
}

LogLine::~LogLine() {
  text_.push_back('\n');
  // One fwrite of the whole line: stdio locks the stream per call.
  std::fwrite(text_.data(), 1, text_.size(), stderr);
}

LogLine& LogLine::Add(absl::string_view key, absl::string_view value) {
  absl::StrAppend(&text_, " ", key, "=");
  AppendValue(text_, value);
  return *this;
}

LogLine& LogLine::Add(absl::string_view key, const char* value) {
  return Add(key, absl::string_view(value));
}

LogLine& LogLine::Add(absl::string_view key, int64_t value) {
  absl::StrAppend(&text_, " ", key, "=", value);
  return *this;
}

LogLine& LogLine::Add(absl::string_view key, uint64_t value) {
  absl::StrAppend(&text_, " ", key, "=", value);
  return *this;
}

LogLine& LogLine::Add(absl::string_view key, int value) { return Add(key, int64_t{value}); }

LogLine& LogLine::Add(absl::string_view key, uint32_t value) {
  return Add(key, uint64_t{value});
}

LogLine& LogLine::Add(absl::string_view key, double value) {
  absl::StrAppend(&text_, " ", key, "=", absl::StrFormat("%.6g", value));
  return *this;
}

}  // namespace fitbase::core
