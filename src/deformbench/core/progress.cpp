#include "core/progress.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fmt/core.h>

namespace db {

namespace {

double interval_seconds(bool tty) {
  if (const char* s = std::getenv("DEFORMBENCH_PROGRESS_SECONDS")) {
    char* end = nullptr;
    const double v = std::strtod(s, &end);
    if (end != s && *end == '\0' && v >= 0) return v;
  }
  return tty ? 1.0 : 10.0;
}

}  // namespace

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

Progress::Progress(std::string label, long long total, bool enabled)
    : label_(std::move(label)), total_(total), enabled_(enabled), tty_(stderr_is_terminal()),
      interval_(interval_seconds(tty_)), next_(interval_) {}

void Progress::operator()(long long done) {
  if (!enabled_) return;
  const double elapsed = clock_.seconds();
  if (elapsed < next_ && !(interval_ == 0)) return;
  next_ = elapsed + interval_;
  const double left = done > 0 ? elapsed * static_cast<double>(total_ - done) / static_cast<double>(done) : 0.0;
  fmt::print(stderr, "{}{} {}/{} ({:.1f}%), {:.0f} s elapsed, about {:.0f} s left{}", tty_ ? "\r" : "", label_, done,
             total_, 100.0 * static_cast<double>(done) / static_cast<double>(total_), elapsed, left, tty_ ? "" : "\n");
  std::fflush(stderr);
  printed_ = true;
}

Progress::~Progress() {
  if (printed_ && tty_) std::fputc('\n', stderr);
}

}  // namespace db
