#include "core/interrupt.h"

#include <atomic>
#include <csignal>
#include <unistd.h>

namespace roger {
namespace {

// Lock-free, so the handler may set it (a sig_atomic_t could not be read across threads).
std::atomic<bool> requested{false};
static_assert(std::atomic<bool>::is_always_lock_free, "a signal handler may only touch lock-free atomics");

extern "C" void on_interrupt(int signal_number) {
  requested.store(true, std::memory_order_relaxed);
  // The next one is the default action: a second Ctrl-C stops at once.
  std::signal(signal_number, SIG_DFL);
  static const char note[] =
      "\nroger: stopping: finishing the episodes in flight, keeping every finished result (press Ctrl-C again "
      "to stop at once)\n";
  const ssize_t ignored = ::write(STDERR_FILENO, note, sizeof note - 1);
  (void)ignored;
}

}  // namespace

void catch_interrupts() {
  // A signal ignored on entry stays ignored, as for every well-behaved program: a shell without
  // job control starts background commands with SIGINT ignored, so a terminal's Ctrl-C is not theirs.
  for (int signal_number : {SIGINT, SIGTERM})
    if (std::signal(signal_number, on_interrupt) == SIG_IGN) std::signal(signal_number, SIG_IGN);
}

bool interrupt_requested() { return requested.load(std::memory_order_relaxed); }

void clear_interrupt() { requested.store(false, std::memory_order_relaxed); }

}  // namespace roger
