#include "pipeline/progress_reporter.h"

#include <unistd.h>

#include <cstdio>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace fitbase::pipeline {
namespace {

// Redrawing more often than this only costs terminal bandwidth.
constexpr std::chrono::milliseconds kRedrawInterval(100);
// Off a terminal (a log, a pipe) a line this often shows a long run is alive without
// flooding the log.
constexpr std::chrono::seconds kLogInterval(60);

std::string FormatSeconds(double seconds) {
  const int64_t s = static_cast<int64_t>(seconds + 0.5);
  if (s >= 3600) return absl::StrFormat("%dh%02dm%02ds", s / 3600, (s / 60) % 60, s % 60);
  if (s >= 60) return absl::StrFormat("%dm%02ds", s / 60, s % 60);
  return absl::StrFormat("%.1fs", seconds);
}

}  // namespace

ProgressReporter::ProgressReporter(std::string label, int64_t total, std::ostream& out,
                                   bool is_terminal, Clock clock)
    : label_(std::move(label)),
      total_(total),
      out_(out),
      is_terminal_(is_terminal),
      clock_(std::move(clock)),
      start_(clock_()),
      last_draw_(start_) {}

void ProgressReporter::Resume(int64_t done) {
  done_at_start_ = done;
  Update(done);
}

void ProgressReporter::Update(int64_t done) {
  done_ = done;
  const auto now = clock_();
  if (!is_terminal_) {
    if (now - last_draw_ < kLogInterval || done_ >= total_) return;
    last_draw_ = now;
    out_ << Line() << '\n' << std::flush;
    return;
  }
  if (now - last_draw_ < kRedrawInterval && done_ < total_) return;
  last_draw_ = now;
  out_ << '\r' << Line() << "\033[K" << std::flush;
}

void ProgressReporter::Finish() {
  if (is_terminal_) out_ << '\r';
  out_ << Line() << (is_terminal_ ? "\033[K\n" : "\n") << std::flush;
}

std::string ProgressReporter::Line() const {
  const double elapsed = std::chrono::duration<double>(clock_() - start_).count();
  std::string line = absl::StrFormat("%s %d/%d  elapsed %s", label_, done_, total_,
                                     FormatSeconds(elapsed));
  const int64_t done_here = done_ - done_at_start_;
  if (done_here > 0 && done_ < total_) {
    const double eta =
        elapsed / static_cast<double>(done_here) * static_cast<double>(total_ - done_);
    absl::StrAppend(&line, "  ETA ", FormatSeconds(eta));
  }
  if (done_at_start_ > 0) absl::StrAppend(&line, "  (", done_at_start_, " at start)");
  return line;
}

bool StderrIsTerminal() { return isatty(fileno(stderr)) != 0; }

}  // namespace fitbase::pipeline
