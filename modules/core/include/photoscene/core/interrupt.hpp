// Ctrl-C as a request, not a kill: the first SIGINT (or SIGTERM) sets a flag that long loops
// check between units of work, so a run stops between whole files; a second one exits at once
// (status 128 + the signal's number: 130 for SIGINT, 143 for SIGTERM).
//
//   ps::InterruptGuard guard;            // installs the handlers for this scope
//   for (...) { ps::checkInterrupted(); ... }   // throws ps::Interrupted once requested
#pragma once

#include <stdexcept>

namespace ps {

/// Thrown by checkInterrupted() after SIGINT / SIGTERM. `signal()` is the signal's number
/// (SIGINT for requestInterrupt()); applications exit with 128 + signal().
class Interrupted : public std::runtime_error {
 public:
  explicit Interrupted(int signal = 2) : std::runtime_error("interrupted"), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

/// Installs SIGINT / SIGTERM handlers for its lifetime (restoring the previous ones after).
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
};

/// True once an interrupt was requested (and until clearInterrupt()).
bool interruptRequested();
/// The signal of the first request (SIGINT or SIGTERM; SIGINT for requestInterrupt()), 0 when none.
int interruptSignal();
/// Requests an interrupt as SIGINT would (for tests and embedding applications).
void requestInterrupt();
void clearInterrupt();
/// Throws ps::Interrupted when an interrupt was requested.
void checkInterrupted();

}  // namespace ps
