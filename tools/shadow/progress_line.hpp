// SPDX-License-Identifier: GPL-3.0-or-later
// Progress of a long run, on a terminal or in a log, for `shadow compute` and `shadow series`.
#pragma once

#include <shadow/shadows.hpp>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>

namespace shadow_cli {

/// "shadow: instants 120/4400 (2%), 3.1/s, about 3 min 10 s left": one line of stderr (stdout
/// stays clean), rewritten in place at most four times a second, erased by finish(). The rate
/// and the time left count only what this process did (a resumed run starts at `base`).
class ProgressLine {
 public:
  using Clock = std::chrono::steady_clock;
  /// `what` names the work items ("face-light pairs", "instants"); nothing is shown unless enabled.
  /// `lines`: for a log rather than a terminal (stderr sent to a file, a batch job's, an MPI
  /// rank's): a new line every log_interval() at most instead of one line rewritten in place,
  /// the first only once that much time has passed (a short run writes none) and a last one at
  /// 100% when any was written.
  ProgressLine(bool enabled, std::string what, std::size_t base = 0, bool lines = false)
      : enabled_(enabled), lines_(lines), what_(std::move(what)), base_(base), start_(Clock::now()),
        last_(lines ? start_ : Clock::time_point{}),
        interval_(lines ? log_interval() : std::chrono::milliseconds(250)) {}
  [[nodiscard]] bool enabled() const { return enabled_; }

  /// The time between two progress lines in a log: 30 s, or LIBSHADOW_PROGRESS_INTERVAL seconds
  /// (a hidden knob for tests, docs/testing.md; 0: a line at every change).
  static std::chrono::milliseconds log_interval() {
    const char* env = std::getenv("LIBSHADOW_PROGRESS_INTERVAL");
    if (env != nullptr && *env != '\0') {
      char* end = nullptr;
      const double seconds = std::strtod(env, &end);
      if (end != env && *end == '\0' && seconds >= 0 && seconds <= 86400)
        return std::chrono::milliseconds(static_cast<long long>(seconds * 1000.0));
    }
    return std::chrono::milliseconds(30000);
  }

  void update(const shadow::Progress& p) {
    if (!enabled_ || p.total == 0) return;
    const auto now = Clock::now();
    const bool last = p.done == p.total;
    if (lines_) {
      if (p.done == last_done_) return;
      if (now - last_ < interval_ && !(last && written_)) return;
    } else if (!last && now - last_ < interval_) {
      return;
    }
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    char eta[48] = "";
    char rate[32] = "";
    const std::size_t done_here = p.done > base_ ? p.done - base_ : 0;
    if (done_here > 0 && elapsed > 0) {
      const double per_second = static_cast<double>(done_here) / elapsed;
      std::snprintf(rate, sizeof rate, per_second >= 10 ? ", %.0f/s" : ", %.2g/s", per_second);
    }
    if (done_here > 0 && p.done < p.total) {
      const double left = elapsed / static_cast<double>(done_here) * static_cast<double>(p.total - p.done);
      if (left >= 60)
        std::snprintf(eta, sizeof eta, ", about %d min %02d s left", static_cast<int>(left) / 60, static_cast<int>(left) % 60);
      else
        std::snprintf(eta, sizeof eta, ", about %d s left", static_cast<int>(left + 0.5));
    }
    std::fprintf(stderr, lines_ ? "shadow: %s %zu/%zu (%d%%)%s%s\n" : "\r\033[Kshadow: %s %zu/%zu (%d%%)%s%s",
                 what_.c_str(), p.done, p.total,
                 static_cast<int>(100.0 * static_cast<double>(p.done) / static_cast<double>(p.total)), rate, eta);
    std::fflush(stderr);
    last_done_ = p.done;
    shown_ = !lines_;
    written_ = true;
  }
  void finish() {
    if (shown_) std::fprintf(stderr, "\r\033[K");
    shown_ = false;
  }

 private:
  bool enabled_;
  bool lines_;
  std::string what_;
  std::size_t last_done_ = SIZE_MAX;
  std::size_t base_;
  bool shown_ = false;
  bool written_ = false;
  Clock::time_point start_;
  Clock::time_point last_;
  std::chrono::milliseconds interval_;
};

}  // namespace shadow_cli
