// Outputs never destroy what they replace (issue 13): a symbolic link is followed, a FIFO or a device
// is written in place, a directory is refused. Every writer goes through AtomicFile.
#include "support.hpp"

#include "engine/atomic_file.hpp"
#include "engine/error.hpp"

#include <doctest/doctest.h>

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <iterator>
#include <thread>

using namespace hemirad;
using namespace hemirad::test;

namespace {

struct stat statOf(const std::string& path, bool follow = true) {
    struct stat st {};
    REQUIRE((follow ? ::stat(path.c_str(), &st) : ::lstat(path.c_str(), &st)) == 0);
    return st;
}

/// `hemirad solve` of the Cornell box (20 patches, LU) with its CSV to `output`.
CommandResult solveTo(const std::string& output) {
    return runCommand(std::string(HEMIRAD_BINARY) + " solve " + sourcePath("scenes/cornell_box.obj") + " --samples 256 -o '" +
                      output + "' --quiet 2>&1");
}

}  // namespace

TEST_CASE("The write decision comes from the file type alone: FIFOs and devices in place, directories refused") {
    const auto dir = tempDir("write-mode");
    CHECK(writeModeFor(false, 0) == WriteMode::Replace);
    writeFile(dir / "regular.csv", "x");
    CHECK(writeModeFor(true, statOf((dir / "regular.csv").string()).st_mode) == WriteMode::Replace);
    REQUIRE(::mkfifo((dir / "fifo").c_str(), 0600) == 0);
    CHECK(writeModeFor(true, statOf((dir / "fifo").string()).st_mode) == WriteMode::Direct);
    CHECK(writeModeFor(true, statOf("/dev/null").st_mode) == WriteMode::Direct);  // stat only: nothing written
    CHECK(writeModeFor(true, statOf(dir.string()).st_mode) == WriteMode::Refuse);
}

TEST_CASE("A FIFO target receives the whole CSV from a reader thread and stays a FIFO") {
    const auto dir = tempDir("fifo-target");
    REQUIRE(solveTo((dir / "regular.csv").string()).status == 0);
    const std::string expected = readText(dir / "regular.csv");
    REQUIRE(expected.size() > 500);
    const std::string fifo = (dir / "out.csv").string();
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    // Opened first and without blocking, so that the test cannot hang even if a regression replaced
    // the FIFO: the reader holds the FIFO itself and gives up after 60 s.
    const int fd = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
    REQUIRE(fd >= 0);
    std::atomic<bool> writerDone{false};
    std::string received;
    std::thread reader([&] {
        char buffer[4096];
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        while (std::chrono::steady_clock::now() < deadline) {
            pollfd p{fd, POLLIN, 0};
            ::poll(&p, 1, 100);
            const ssize_t n = ::read(fd, buffer, sizeof buffer);
            if (n > 0) received.append(buffer, std::size_t(n));
            else if (n == 0 && writerDone.load()) break;  // no writer left and everything read
        }
    });
    const CommandResult run = solveTo(fifo);
    writerDone = true;
    reader.join();
    ::close(fd);
    CHECK_MESSAGE(run.status == 0, run.output);
    CHECK(received == expected);
    CHECK(S_ISFIFO(statOf(fifo, false).st_mode));
    for (const auto& entry : std::filesystem::directory_iterator(dir))  // no temporary file left beside it
        CHECK(entry.path().filename().string().find("hemirad-tmp") == std::string::npos);
}

TEST_CASE("A symbolic link target stays a link and the file it points to is replaced atomically") {
    const auto dir = tempDir("symlink-target");
    std::filesystem::create_directories(dir / "results");
    REQUIRE(solveTo((dir / "regular.csv").string()).status == 0);
    const std::string expected = readText(dir / "regular.csv");
    writeFile(dir / "results" / "real.csv", "old content\n");
    std::filesystem::create_symlink("results/real.csv", dir / "link.csv");  // relative, from the link's folder
    std::filesystem::create_symlink(dir / "link.csv", dir / "chain.csv");   // a link to a link
    std::filesystem::create_symlink("results/new.csv", dir / "dangling.csv");
    for (const char* name : {"link.csv", "chain.csv", "dangling.csv"}) {
        CAPTURE(name);
        const CommandResult run = solveTo((dir / name).string());
        REQUIRE_MESSAGE(run.status == 0, run.output);
        CHECK(S_ISLNK(statOf((dir / name).string(), false).st_mode));
    }
    CHECK(readText(dir / "results" / "real.csv") == expected);
    CHECK(readText(dir / "results" / "new.csv") == expected);
    std::filesystem::create_symlink("loop.csv", dir / "loop.csv");
    const CommandResult loop = solveTo((dir / "loop.csv").string());
    CHECK(loop.status == 1);
    CHECK(loop.output.find("too many levels of symbolic links") != std::string::npos);
}

TEST_CASE("A directory target is refused with a clear error and left as it was") {
    const auto dir = tempDir("directory-target");
    std::filesystem::create_directories(dir / "out.csv");
    const CommandResult run = solveTo((dir / "out.csv").string());
    CHECK(run.status == 1);
    CHECK(run.output.find("out.csv: is a directory; give a file name to write") != std::string::npos);
    CHECK(std::filesystem::is_directory(dir / "out.csv"));
}

TEST_CASE("formfactors -o /dev/null, run as user nobody (65534) when the tests run as root, leaves /dev/null a device") {
    // Run unprivileged so that a regression could never replace the machine's /dev/null: as nobody the
    // rename onto /dev/null (in root's /dev) would fail instead. The binary and the scene are copied to
    // a folder nobody can read, whatever folder the build lies in.
    char pattern[] = "/tmp/hemirad-nobody-XXXXXX";
    REQUIRE(::mkdtemp(pattern) != nullptr);
    const std::filesystem::path dir(pattern);
    REQUIRE(::chmod(pattern, 0755) == 0);
    namespace fs = std::filesystem;
    fs::copy_file(HEMIRAD_BINARY, dir / "hemirad");
    fs::copy_file(sourcePath("scenes/cornell_box.obj"), dir / "cornell_box.obj");
    fs::copy_file(sourcePath("scenes/cornell_box.mtl"), dir / "cornell_box.mtl");
    for (const char* name : {"hemirad", "cornell_box.obj", "cornell_box.mtl"}) ::chmod((dir / name).c_str(), 0755);
    const std::string binary = (dir / "hemirad").string(), scene = (dir / "cornell_box.obj").string();
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) ::_exit(90);
        ::execl(binary.c_str(), binary.c_str(), "formfactors", scene.c_str(), "--samples", "256", "-o", "/dev/null",
                "--quiet", static_cast<char*>(nullptr));
        ::_exit(91);
    }
    int status = 0;
    REQUIRE(::waitpid(child, &status, 0) == child);
    fs::remove_all(dir);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);  // 90: could not become nobody; 91: could not run hemirad
    CHECK(S_ISCHR(statOf("/dev/null", false).st_mode));
}

TEST_CASE("Hostile output paths: spaces and non-ASCII work, a 250-character name works, a 300-character one is a clear error") {
    const auto dir = tempDir("hostile-outputs");
    REQUIRE(solveTo((dir / "regular.csv").string()).status == 0);
    const std::string expected = readText(dir / "regular.csv");
    for (const std::string name : {std::string("with space é ü 光.csv"), std::string(246, 'n') + ".csv"}) {
        CAPTURE(name.size());
        const CommandResult run = solveTo((dir / name).string());
        CHECK_MESSAGE(run.status == 0, run.output);
        CHECK(readText(dir / name) == expected);
    }
    const std::string tooLong = std::string(296, 'n') + ".csv";
    const CommandResult run = solveTo((dir / tooLong).string());
    CHECK(run.status == 1);
    CHECK(run.output.find("cannot write: File name too long") != std::string::npos);
    for (const auto& entry : std::filesystem::directory_iterator(dir))
        CHECK(entry.path().filename().string().find("hemirad-tmp") == std::string::npos);
}

TEST_CASE("A read-only target, written by a child running as nobody (65534) when the tests run as root, is refused and kept") {
    // As root every file is writable, so the child drops to nobody; the folder is nobody's, so only the
    // file's own mode protects it (a rename in a writable folder would replace it).
    char pattern[] = "/tmp/hemirad-readonly-XXXXXX";
    REQUIRE(::mkdtemp(pattern) != nullptr);
    const std::filesystem::path dir(pattern);
    namespace fs = std::filesystem;
    fs::copy_file(HEMIRAD_BINARY, dir / "hemirad");
    fs::copy_file(sourcePath("scenes/cornell_box.obj"), dir / "cornell_box.obj");
    fs::copy_file(sourcePath("scenes/cornell_box.mtl"), dir / "cornell_box.mtl");
    writeFile(dir / "kept.csv", "precious\n");
    for (const char* name : {"hemirad", "cornell_box.obj", "cornell_box.mtl"}) ::chmod((dir / name).c_str(), 0755);
    ::chmod((dir / "kept.csv").c_str(), 0444);
    if (::geteuid() == 0) {
        REQUIRE(::chown(pattern, 65534, 65534) == 0);
        REQUIRE(::chown((dir / "kept.csv").c_str(), 65534, 65534) == 0);
    }
    ::chmod(pattern, 0755);
    const std::string binary = (dir / "hemirad").string(), scene = (dir / "cornell_box.obj").string();
    const std::string target = (dir / "kept.csv").string(), log = (dir / "log.txt").string();
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) ::_exit(90);
        const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (out < 0) ::_exit(92);
        ::dup2(out, 2);
        ::execl(binary.c_str(), binary.c_str(), "solve", scene.c_str(), "--samples", "256", "-o", target.c_str(),
                static_cast<char*>(nullptr));
        ::_exit(91);
    }
    int status = 0;
    REQUIRE(::waitpid(child, &status, 0) == child);
    const std::string message = readText(log), kept = readText(target);
    fs::remove_all(dir);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 1);  // 90: could not become nobody; 91: could not run hemirad; 92: no log
    CHECK(message.find("kept.csv: cannot write: Permission denied") != std::string::npos);
    CHECK(kept == "precious\n");
}
