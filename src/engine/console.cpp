// One write per message on standard output and standard error (see console.hpp).
#include "engine/console.hpp"

#include <cerrno>
#include <cstdio>
#include <iostream>

#include <unistd.h>

namespace hemirad {
namespace {

void writeDescriptor(int descriptor, std::string_view text) noexcept {
    while (!text.empty()) {
        const ssize_t n = ::write(descriptor, text.data(), text.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return;  // nowhere to say it
        text.remove_prefix(std::size_t(n));
    }
}

}  // namespace

void writeWhole(std::ostream& stream, std::string_view text) noexcept {
    try {
        const int descriptor = &stream == &std::cout ? STDOUT_FILENO
                               : &stream == &std::cerr || &stream == &std::clog ? STDERR_FILENO
                                                                                 : -1;
        if (descriptor < 0) {
            stream << text << std::flush;
            return;
        }
        // What the stream and C's stdio hold goes first, so that the order of messages stays.
        stream.flush();
        std::fflush(descriptor == STDOUT_FILENO ? stdout : stderr);
        writeDescriptor(descriptor, text);
    } catch (...) {
        // A stream set to throw, or no memory: a message that cannot be written is dropped.
    }
}

void printError(const std::string& message, bool usage) noexcept {
    try {
        writeWhole(std::cerr, "hemirad: error: " + message + (usage ? "\n(run 'hemirad help' for usage)\n" : "\n"));
    } catch (...) {
        writeWhole(std::cerr, "hemirad: error: out of memory\n");
    }
}

}  // namespace hemirad
