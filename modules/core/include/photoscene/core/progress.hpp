// A progress reporter for long stages: a live bar on a terminal, periodic log lines otherwise
// (CI logs, pipes). Thread-safe: advance() may be called from parallel loops.
//
//   ps::Progress progress("fit parts", parts.size());
//   ps::parallelFor(0, n, [&](int64_t i) { fit(i); progress.advance(); });
//   progress.finish();   // also called by the destructor
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace ps {

struct ProgressOptions {
  /// Auto: a live bar when stderr is a terminal, log lines otherwise.
  enum class Mode { Auto, Bar, Log, Silent } mode = Mode::Auto;
  /// Log mode: a line at least every this many seconds, and at every 10% step.
  double logIntervalSeconds = 5.0;
  /// Bar mode: redraw at most this often.
  double redrawSeconds = 0.1;
};

class Progress {
 public:
  Progress(std::string label, int64_t total, ProgressOptions options = {});
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Marks n more units done.
  void advance(int64_t n = 1);
  /// Marks the task complete and prints the final line (once).
  void finish();
  int64_t done() const { return done_.load(); }
  int64_t total() const { return total_; }
  double elapsedSeconds() const;
  /// The mode in use after resolving Auto.
  ProgressOptions::Mode mode() const { return mode_; }

  /// Applies to every Progress created afterwards in this process (the app's --quiet flag).
  static void setDefaultMode(ProgressOptions::Mode mode);

 private:
  void report(bool final);

  std::string label_;
  int64_t total_;
  ProgressOptions options_;
  ProgressOptions::Mode mode_;
  std::atomic<int64_t> done_{0};
  std::chrono::steady_clock::time_point start_, lastReport_;
  int lastDecile_ = -1;
  bool finished_ = false;
  std::mutex mutex_;
};

}  // namespace ps
