#include "photoscene/core/interrupt.hpp"

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <unistd.h>

namespace ps {

namespace {

std::atomic<int> g_requests{0};
struct sigaction g_oldInt, g_oldTerm;
int g_guards = 0;

extern "C" void onSignal(int) {
  if (g_requests.fetch_add(1) >= 1) _exit(130);  // the second one: stop now
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
void requestInterrupt() { g_requests.store(1); }
void clearInterrupt() { g_requests.store(0); }

void checkInterrupted() {
  if (interruptRequested()) throw Interrupted();
}

}  // namespace ps
