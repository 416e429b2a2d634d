#include "photoscene/core/interrupt.hpp"

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <unistd.h>

namespace ps {

namespace {

std::atomic<int> g_requests{0};
std::atomic<int> g_signal{0};
struct sigaction g_oldInt, g_oldTerm;
int g_guards = 0;

extern "C" void onSignal(int sig) {
  int none = 0;
  g_signal.compare_exchange_strong(none, sig);         // the first signal names the request
  if (g_requests.fetch_add(1) >= 1) _exit(128 + sig);  // the second one: stop now
  static const char msg[] = "\ninterrupt: stopping at the next check point (again to quit now)\n";
  [[maybe_unused]] ssize_t n = write(STDERR_FILENO, msg, sizeof(msg) - 1);
}

}  // namespace

InterruptGuard::InterruptGuard() {
  if (g_guards++ > 0) return;
  struct sigaction sa{};
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &g_oldInt);
  sigaction(SIGTERM, &sa, &g_oldTerm);
}

InterruptGuard::~InterruptGuard() {
  if (--g_guards > 0) return;
  sigaction(SIGINT, &g_oldInt, nullptr);
  sigaction(SIGTERM, &g_oldTerm, nullptr);
}

bool interruptRequested() { return g_requests.load() > 0; }
int interruptSignal() {
  if (!interruptRequested()) return 0;
  const int s = g_signal.load();
  return s ? s : SIGINT;
}
void requestInterrupt() { g_requests.store(1); }
void clearInterrupt() {
  g_requests.store(0);
  g_signal.store(0);
}

void checkInterrupted() {
  if (interruptRequested()) throw Interrupted(interruptSignal());
}

}  // namespace ps
