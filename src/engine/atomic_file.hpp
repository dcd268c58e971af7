// Every output file goes through AtomicFile. A regular file (or none yet) is written atomically: data
// goes to a temporary file beside the target (.NAME.hemirad-tmp.HOST.PID.UNIQUE, created exclusively),
// which is synced to disk and renamed over it on commit(), the folder synced after. The new file keeps
// the old one's permission bits and, where the process may set them, its owner and group; a
// read-only file is refused. Rename semantics: the target's name gets a new file, so a hard link to
// the old one keeps the old content (a rewrite in place could not be atomic). What is not a regular
// file is never replaced: a symbolic link is followed to its target, and a FIFO, device or socket is
// written in place. The path "-" is standard output (binary data refused when it is a terminal).
#pragma once

#include <fstream>
#include <ostream>
#include <string>

#include <sys/types.h>

namespace hemirad {

/// How a write reaches an existing target (or none).
enum class WriteMode {
    Replace,  ///< a regular file, or nothing there yet: temporary file beside it, renamed onto it
    Direct,   ///< a FIFO, character or block device or socket: opened and written in place (not atomic)
    Refuse,   ///< a directory
};

/// The path that names standard output.
inline bool isStandardOutput(const std::string& path) { return path == "-"; }

/// Throws hemirad::Error when binary data would go to standard output and it is a terminal.
void requireBinaryStandardOutput();

/// The mode for a target whose stat() gave `mode` (`exists` false: nothing there). Decides from the
/// file type alone, so that tests can check it on /dev/null without writing there.
WriteMode writeModeFor(bool exists, mode_t mode);

/// The path a write to `path` lands on: symbolic links followed (relative targets from the link's
/// folder); the final target may not exist yet. Throws hemirad::Error naming `path` for a loop.
std::string resolveWriteTarget(const std::string& path);

/// Whether a write to `path` goes in place (standard output, or it resolves to an existing FIFO,
/// device or socket): such a target has no file name extension to choose a format by. Never throws.
bool writesInPlace(const std::string& path);

/// Write through stream(), then commit(). Destroyed without commit (an exception, Ctrl-C via
/// removePendingFiles()), the temporary file is removed and the target is untouched (a target
/// written in place keeps what was written).
class AtomicFile {
public:
    /// `binary`: the data is not text; "-" is then refused (hemirad::Error) when standard output is a
    /// terminal.
    explicit AtomicFile(std::string path, bool binary = true);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ostream& stream() { return *m_out; }
    /// Flushes, checks for write errors, syncs the data to disk and renames into place, then syncs
    /// the folder (best effort: some file systems cannot); closes a target written in place.
    /// Throws hemirad::Error.
    void commit();
    /// The temporary file being written ("" for a target written in place or standard output).
    const std::string& temporaryPath() const { return m_temp; }

    /// The name of a temporary file for `target` in its folder: ".NAME.hemirad-tmp.HOST.PID.UNIQUE",
    /// NAME shortened (at a UTF-8 boundary) so that the whole fits one folder entry (255 bytes). The
    /// host name keeps nodes that share a folder and run equal PIDs (containers) apart; UNIQUE is
    /// a per-process random number and a counter, and the file is created with O_EXCL anyway.
    static std::string temporaryNameFor(const std::string& target);

    /// Deletes every temporary file not yet committed; async-signal-safe (for SIGINT handlers).
    static void removePendingFiles() noexcept;
    /// Installs SIGINT and SIGTERM handlers that delete them, say "interrupted; no partial output
    /// was written" on stderr and exit with 128 + the signal. Per copy of this library: hemirad and
    /// its MPI module (which carries its own) each install theirs.
    static void removePendingFilesOnInterrupt();
    /// From now on those handlers exit with `status` (1 if 0) and say nothing: for a process whose
    /// failure was already reported (an error all MPI ranks agreed on), which mpirun may still send
    /// SIGTERM while it finalises; "interrupted" would contradict the reported error. Per copy of
    /// this library, as the handlers are.
    static void exitQuietlyOnInterrupt(int status) noexcept;

private:
    /// Closes and removes the temporary file (nothing for a target written in place).
    void discard() noexcept;

    std::string m_shown;  ///< the path as given, for messages
    std::string m_path;   ///< the resolved target
    std::string m_temp;   ///< empty when writing in place
    std::ofstream m_file;
    int m_descriptor = -1;          ///< the temporary file, held open for fsync
    std::ostream* m_out = &m_file;  ///< m_file, or std::cout for "-"
    bool m_committed = false;
};

}  // namespace hemirad
