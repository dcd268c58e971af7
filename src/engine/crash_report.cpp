// Fatal-signal report: async-signal-safe writes, the frames from glibc's backtrace.
#include "engine/crash_report.hpp"

#include "engine/atomic_file.hpp"

#include <execinfo.h>
#include <unistd.h>

#include <csignal>
#include <cstring>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define HEMIRAD_SANITIZER_HANDLES_SIGNALS 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define HEMIRAD_SANITIZER_HANDLES_SIGNALS 1
#endif
#endif

namespace hemirad {
namespace {

const char* g_program = "hemirad";
// The main thread's handler stack: a stack overflow there leaves none to run on.
alignas(16) char g_stack[64 * 1024];

void say(const char* text) {
    for (std::size_t left = std::strlen(text); left > 0;) {
        const ssize_t n = ::write(STDERR_FILENO, text, left);
        if (n <= 0) return;
        text += n;
        left -= std::size_t(n);
    }
}

const char* signalName(int signal) {
    switch (signal) {
        case SIGSEGV: return "segmentation fault (SIGSEGV)";
        case SIGBUS: return "bus error (SIGBUS)";
        case SIGFPE: return "arithmetic exception (SIGFPE)";
        case SIGILL: return "illegal instruction (SIGILL)";
        case SIGABRT: return "aborted (SIGABRT)";
        default: return "fatal signal";
    }
}

extern "C" void onFatalSignal(int signal) {
    AtomicFile::removePendingFiles();
    say("\n");
    say(g_program);
    say(": internal error: ");
    say(signalName(signal));
    say("; no partial output was written. Stack:\n");
    void* frames[64];
    const int count = ::backtrace(frames, 64);
    ::backtrace_symbols_fd(frames, count, STDERR_FILENO);
    say("Please report it with the command line, the scene and this stack.\n");
    // Blocked while this handler runs: delivered, with the default action, when it returns.
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

}  // namespace

void reportFatalSignals(const char* program) {
#ifndef HEMIRAD_SANITIZER_HANDLES_SIGNALS
    g_program = program;
    void* warm[1];
    ::backtrace(warm, 1);  // loads libgcc's unwinder now, not in the handler
    stack_t stack{};
    stack.ss_sp = g_stack;
    stack.ss_size = sizeof g_stack;
    ::sigaltstack(&stack, nullptr);
    struct sigaction action {};
    action.sa_handler = onFatalSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_ONSTACK;
    for (const int signal : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) ::sigaction(signal, &action, nullptr);
#else
    (void)program;
#endif
}

}  // namespace hemirad
