// What a process says when it dies of a fatal signal.
#pragma once

namespace hemirad {

/// Installs handlers for SIGSEGV, SIGBUS, SIGFPE, SIGILL and SIGABRT: the pending atomic files are
/// removed (no partial output), standard error gets "PROGRAM: internal error: SIGNAL" with the
/// stack's frames (addresses within their libraries, for addr2line) and what to report, and the
/// process then dies of the same signal (exit status 128 + N, a core where cores are enabled), as
/// it would have without the handler. Not installed in sanitizer builds, whose own reports are
/// better. Call once, early, from a program's main.
void reportFatalSignals(const char* program);

}  // namespace hemirad
