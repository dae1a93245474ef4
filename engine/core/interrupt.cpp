#include "core/interrupt.h"

#include <atomic>
#include <csignal>
#include <cstdint>
#include <ctime>
#include <unistd.h>

namespace roger {
namespace {

// Lock-free, so the handler may set it (a sig_atomic_t could not be read across threads).
std::atomic<bool> requested{false};
std::atomic<int> requested_by{0};  // the signal of the first request
// What the command does on the first request, after "roger: stopping" (catch_interrupts).
std::atomic<const char*> stopping_note{nullptr};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free &&
                  std::atomic<const char*>::is_always_lock_free,
              "a signal handler may only touch lock-free atomics");

// write(2) of a whole C string, the one output a signal handler may make.
void write_stderr(const char* text) {
  size_t n = 0;
  while (text[n]) ++n;
  const ssize_t ignored = ::write(STDERR_FILENO, text, n);
  (void)ignored;
}

std::atomic<int64_t> first_at_ns{0};  // when the first request came (CLOCK_MONOTONIC)
static_assert(std::atomic<int64_t>::is_always_lock_free, "a signal handler may only touch lock-free atomics");

int64_t monotonic_ns() {
  timespec t{};
  ::clock_gettime(CLOCK_MONOTONIC, &t);  // async-signal-safe
  return int64_t(t.tv_sec) * 1000000000 + t.tv_nsec;
}

// A second signal this soon after the first is the same request delivered twice: GNU timeout sends
// its signal to the command and again to its process group, microseconds apart, and a user's second
// Ctrl-C never comes within 20 ms.
constexpr int64_t kSameRequestNs = 20000000;

extern "C" void on_interrupt(int signal_number) {
  const bool term = signal_number == SIGTERM;
  if (requested.load(std::memory_order_relaxed)) {
    if (monotonic_ns() - first_at_ns.load(std::memory_order_relaxed) < kSameRequestNs) return;
    // A second request stops at once: the signal's default action, once the handler returns.
    write_stderr(term ? "\nroger: stopped at once by a second SIGTERM\n" : "\nroger: stopped at once by a second Ctrl-C\n");
    std::signal(signal_number, SIG_DFL);
    std::raise(signal_number);
    return;
  }
  first_at_ns.store(monotonic_ns(), std::memory_order_relaxed);
  requested_by.store(signal_number, std::memory_order_relaxed);
  requested.store(true, std::memory_order_relaxed);
  write_stderr(term ? "\nroger: stopping (SIGTERM): " : "\nroger: stopping: ");
  const char* note = stopping_note.load(std::memory_order_relaxed);
  write_stderr(note ? note : "finishing the episodes in flight, keeping every finished result");
  write_stderr(term ? " (a second SIGTERM stops at once)\n" : " (press Ctrl-C again to stop at once)\n");
}

// The output's reader went away (`roger run ... | head -1` once head has its line): as a stop
// request, so that the run keeps what finished and its status says interrupted. Without it the
// pipe's SIGPIPE killed the run before its status was written. Said once, silently after: each
// later write to the closed pipe raises SIGPIPE again, and saying so would raise it once more.
extern "C" void on_broken_pipe(int) {
  if (requested.load(std::memory_order_relaxed)) return;
  first_at_ns.store(monotonic_ns(), std::memory_order_relaxed);
  requested_by.store(SIGPIPE, std::memory_order_relaxed);
  requested.store(true, std::memory_order_relaxed);
  write_stderr("\nroger: stopping (the output's reader closed the pipe): ");
  const char* note = stopping_note.load(std::memory_order_relaxed);
  write_stderr(note ? note : "finishing the episodes in flight, keeping every finished result");
  write_stderr("\n");
}

}  // namespace

void catch_interrupts(const char* stopping) {
  stopping_note.store(stopping, std::memory_order_relaxed);
  // A signal ignored on entry stays ignored, as for every well-behaved program: a shell without
  // job control starts background commands with SIGINT ignored, so a terminal's Ctrl-C is not theirs.
  for (int signal_number : {SIGINT, SIGTERM})
    if (std::signal(signal_number, on_interrupt) == SIG_IGN) std::signal(signal_number, SIG_IGN);
  if (std::signal(SIGPIPE, on_broken_pipe) == SIG_IGN) std::signal(SIGPIPE, SIG_IGN);
}

bool interrupt_requested() { return requested.load(std::memory_order_relaxed); }

int interrupt_exit_status() {
  const int by = requested_by.load(std::memory_order_relaxed);
  return 128 + (by > 0 ? by : SIGINT);
}

void clear_interrupt() {
  first_at_ns.store(0, std::memory_order_relaxed);
  requested.store(false, std::memory_order_relaxed);
  requested_by.store(0, std::memory_order_relaxed);
}

}  // namespace roger
