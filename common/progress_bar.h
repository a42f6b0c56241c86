// A progress bar with an elapsed time and an ETA on stderr, for a program's long loops
// (run_experiment's jobs): `[####......] 12/40  30.0%  elapsed 0:04  ETA 0:09`, redrawn at most
// every 0.2 s, ended with a newline when done == total; `extra` is appended (track_images: frames
// per second and lines). Shown on a terminal only by default (a log would get one long line of
// redraws); a hidden bar draws nothing.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace slt {

inline bool StderrIsTerminal() { return ::isatty(STDERR_FILENO) != 0; }

class ProgressBar {
 public:
  explicit ProgressBar(bool shown = StderrIsTerminal()) : shown_(shown) {}
  bool shown() const { return shown_; }

  void Update(size_t done, size_t total, const std::string& extra = "") {
    if (!shown_) return;
    const auto now = std::chrono::steady_clock::now();
    if (done < total && now - last_draw_ < std::chrono::milliseconds(200)) return;
    last_draw_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double fraction = total ? static_cast<double>(done) / static_cast<double>(total) : 1.0;
    const int width = 30;
    const int filled = static_cast<int>(fraction * width);
    std::string bar(static_cast<size_t>(filled), '#');
    bar.resize(width, '.');
    std::string eta = "--:--";
    if (done > 0) eta = Clock(elapsed / static_cast<double>(done) * static_cast<double>(total - done));
    std::fprintf(stderr, "\r[%s] %zu/%zu %5.1f%%  elapsed %s  ETA %s %s", bar.c_str(), done, total, 100.0 * fraction,
                 Clock(elapsed).c_str(), eta.c_str(), extra.c_str());
    if (done == total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }

 private:
  static std::string Clock(double seconds) {
    const long s = static_cast<long>(seconds + 0.5);
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%ld:%02ld", s / 60, s % 60);
    return buffer;
  }
  bool shown_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_draw_{};
};

}  // namespace slt
