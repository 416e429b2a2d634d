#include "photoscene/core/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "photoscene/core/log.hpp"

namespace ps {

namespace {
std::atomic<int> gDefaultMode{static_cast<int>(ProgressOptions::Mode::Auto)};
}

void Progress::setDefaultMode(ProgressOptions::Mode mode) { gDefaultMode = static_cast<int>(mode); }

Progress::Progress(std::string label, int64_t total, ProgressOptions options)
    : label_(std::move(label)), total_(std::max<int64_t>(total, 0)), options_(options) {
  mode_ = options_.mode;
  if (mode_ == ProgressOptions::Mode::Auto)
    mode_ = static_cast<ProgressOptions::Mode>(gDefaultMode.load());
  if (mode_ == ProgressOptions::Mode::Auto)
    mode_ = isatty(STDERR_FILENO) ? ProgressOptions::Mode::Bar : ProgressOptions::Mode::Log;
  start_ = lastReport_ = std::chrono::steady_clock::now();
}

Progress::~Progress() { finish(); }

double Progress::elapsedSeconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::advance(int64_t n) {
  done_.fetch_add(n);
  if (mode_ == ProgressOptions::Mode::Silent) return;
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;  // another thread is reporting; skip rather than wait
  report(false);
}

void Progress::finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  finished_ = true;
  if (mode_ != ProgressOptions::Mode::Silent) report(true);
}

void Progress::report(bool final) {
  const auto now = std::chrono::steady_clock::now();
  const double sinceLast = std::chrono::duration<double>(now - lastReport_).count();
  const int64_t done = std::min(done_.load(), total_ > 0 ? total_ : done_.load());
  const double frac = total_ > 0 ? static_cast<double>(done) / total_ : 1.0;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (mode_ == ProgressOptions::Mode::Bar) {
    if (!final && sinceLast < options_.redrawSeconds) return;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(frac * kWidth + 0.5);
    std::string bar(filled, '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r[photoscene] %-18s [%s] %3d%% %lld/%lld %.1fs%s", label_.c_str(),
                 bar.c_str(), static_cast<int>(frac * 100 + 0.5), static_cast<long long>(done),
                 static_cast<long long>(total_), elapsed, final ? "\n" : "");
    std::fflush(stderr);
  } else {
    const int decile = static_cast<int>(frac * 10);
    if (!final && decile == lastDecile_ && sinceLast < options_.logIntervalSeconds) return;
    if (!final && decile == lastDecile_ && done == 0) return;
    lastDecile_ = decile;
    spdlog::info("{}: {}/{} ({:.0f}%) {:.1f}s{}", label_, done, total_, frac * 100, elapsed,
                 final ? " done" : "");
  }
  lastReport_ = now;
}

}  // namespace ps
