// interrupt.h: Ctrl-C (SIGINT), SIGTERM or a closed output pipe (SIGPIPE) as a request to stop a
// long command cleanly. A batch run asks for it (roger run); its episodes then end at their next
// start with Interrupted, its trials in flight are left to run again on resume, and it writes
// what it has (docs/reliability.md).
#pragma once

#include "core/error.h"

namespace roger {

// The first SIGINT or SIGTERM sets the request (and says on stderr that the command is stopping,
// then `stopping`, what it does now: a string that lives as long as the program; by default a
// batch run's "finishing the episodes in flight, keeping every finished result"); the second stops
// the process at once, as the signal's default action would. A closed output pipe (SIGPIPE: the
// reader of `roger run ... | head` went away) is a request too, never escalated: writes to the pipe
// then fail and are lost.
void catch_interrupts(const char* stopping = nullptr);

// Whether a stop was requested since catch_interrupts. Cheap: read at every episode's start.
bool interrupt_requested();

// The exit status of a command that stopped on request, as a shell reports a command the signal
// stopped: 130 after SIGINT (Ctrl-C), 143 after SIGTERM (Slurm's scancel, a time limit, kill), 141
// after a closed output pipe.
int interrupt_exit_status();

// Forgets a request (tests, and a command that has finished stopping).
void clear_interrupt();

// Thrown where a requested stop ends work part-way (an episode not started).
struct Interrupted : Error {
  Interrupted() : Error("interrupted (Ctrl-C, SIGTERM or a closed output pipe)") {}
};

// Throws Interrupted when a stop was requested.
inline void throw_if_interrupted() {
  if (interrupt_requested()) throw Interrupted();
}

}  // namespace roger
