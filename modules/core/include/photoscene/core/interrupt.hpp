// Ctrl-C as a request, not a kill: the first SIGINT (or SIGTERM) sets a flag that long loops
// check between units of work, so a run stops between whole files; a second one exits at once.
//
//   ps::InterruptGuard guard;            // installs the handlers for this scope
//   for (...) { ps::checkInterrupted(); ... }   // throws ps::Interrupted once requested
#pragma once

#include <stdexcept>

namespace ps {

/// Thrown by checkInterrupted() after SIGINT / SIGTERM.
class Interrupted : public std::runtime_error {
 public:
  Interrupted() : std::runtime_error("interrupted") {}
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
/// Requests an interrupt as SIGINT would (for tests and embedding applications).
void requestInterrupt();
void clearInterrupt();
/// Throws ps::Interrupted when an interrupt was requested.
void checkInterrupted();

}  // namespace ps
