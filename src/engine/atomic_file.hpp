// Atomic file writes: data goes to a temporary file beside the target, renamed over it on commit().
#pragma once

#include <fstream>
#include <string>

namespace hemirad {

/// Write through stream(), then commit(). Destroyed without commit (an exception, Ctrl-C via
/// removePendingFiles()), the temporary file is removed and the target is untouched.
class AtomicFile {
public:
    explicit AtomicFile(std::string path, bool binary = true);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ofstream& stream() { return m_out; }
    /// Flushes, checks for write errors and renames into place. Throws hemirad::Error.
    void commit();

    /// Deletes every temporary file not yet committed; async-signal-safe (for SIGINT handlers).
    static void removePendingFiles() noexcept;

private:
    std::string m_path;
    std::string m_temp;
    std::ofstream m_out;
    bool m_committed = false;
};

}  // namespace hemirad
