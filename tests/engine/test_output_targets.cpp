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
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <thread>
#include <vector>

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
    for (const std::string& name : {std::string("with space é ü 光.csv"), std::string(246, 'n') + ".csv"}) {
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

namespace {

/// hemirad ARGUMENTS run in `dir` with standard output to out.txt and standard error to err.txt.
CommandResult runToFiles(const std::filesystem::path& dir, const std::string& arguments) {
    return runCommand("cd '" + dir.string() + "' && " + std::string(HEMIRAD_BINARY) + " " + arguments +
                      " > out.txt 2> err.txt");
}

/// Runs hemirad ARGUMENTS with its standard output on a pseudo-terminal (standard error to `log`);
/// returns the exit status.
int runOnTerminal(const std::vector<std::string>& arguments, const std::string& log) {
    const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
    REQUIRE(master >= 0);
    REQUIRE(::grantpt(master) == 0);
    REQUIRE(::unlockpt(master) == 0);
    const std::string terminal = ::ptsname(master);
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        const int slave = ::open(terminal.c_str(), O_RDWR | O_NOCTTY);
        const int err = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (slave < 0 || err < 0) ::_exit(92);
        ::dup2(slave, 1);
        ::dup2(err, 2);
        std::vector<char*> argv;
        argv.push_back(const_cast<char*>(HEMIRAD_BINARY));
        for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(HEMIRAD_BINARY, argv.data());
        ::_exit(91);
    }
    // Whatever reaches the terminal is drained, so that the child cannot block on a full buffer.
    int status = 0;
    char buffer[4096];
    ::fcntl(master, F_SETFL, O_NONBLOCK);
    while (::waitpid(child, &status, WNOHANG) == 0) {
        while (::read(master, buffer, sizeof buffer) > 0) {
        }
        ::usleep(10000);
    }
    ::close(master);
    REQUIRE(WIFEXITED(status));
    return WEXITSTATUS(status);
}

}  // namespace

TEST_CASE("-o - writes the CSV and the Matrix Market F to standard output, the report to standard error, and they round-trip") {
    const auto dir = tempDir("stdout-text");
    const std::string scene = sourcePath("scenes/cornell_box.obj") + " --samples 256 --threads 1";
    REQUIRE(runToFiles(dir, "solve " + scene + " -o B.csv").status == 0);
    const std::string csv = readText(dir / "B.csv");
    REQUIRE(csv.size() > 500);

    CommandResult run = runToFiles(dir, "solve " + scene + " -o -");
    REQUIRE(run.status == 0);
    CHECK(readText(dir / "out.txt") == csv);  // the CSV alone: no report line among its rows
    CHECK(readText(dir / "err.txt").find("wrote standard output") != std::string::npos);
    CHECK(readText(dir / "err.txt").find("scene: ") != std::string::npos);
    // Through a pipe into another program, as a user would.
    const CommandResult piped = runCommand("cd '" + dir.string() + "' && " + HEMIRAD_BINARY + " solve " + scene +
                                           " -o - 2>/dev/null | cat");
    CHECK(piped.status == 0);
    CHECK(piped.output == csv);

    // F as Matrix Market through a pipe (the default on standard output), read back by solve --ff.
    REQUIRE(runToFiles(dir, "formfactors " + scene + " -o F.mtx").status == 0);
    const CommandResult mtx = runCommand("cd '" + dir.string() + "' && " + HEMIRAD_BINARY + " formfactors " + scene +
                                         " -o - 2>/dev/null | cat > piped.mtx");
    REQUIRE(mtx.status == 0);
    CHECK(readText(dir / "piped.mtx").rfind("%%MatrixMarket", 0) == 0);
    CHECK(readText(dir / "piped.mtx") == readText(dir / "F.mtx"));
    run = runToFiles(dir, "solve " + scene + " --ff piped.mtx -o -");
    REQUIRE(run.status == 0);
    CHECK(readText(dir / "err.txt").find("reused piped.mtx") != std::string::npos);
    CHECK(readText(dir / "out.txt") == csv);

    // /dev/stdout is a link to a pipe that has no path: written in place too.
    const CommandResult devStdout = runCommand("cd '" + dir.string() + "' && " + HEMIRAD_BINARY + " solve " + scene +
                                               " -o /dev/stdout --format csv --quiet | cat");
    CHECK(devStdout.status == 0);
    CHECK(devStdout.output == csv);
}

TEST_CASE("-o - writes binary .hff and PNG to a pipe, and refuses them on a terminal before any work") {
    const auto dir = tempDir("stdout-binary");
    const std::string scene = sourcePath("scenes/cornell_box.obj");
    REQUIRE(runToFiles(dir, "formfactors " + scene + " --samples 256 --threads 1 -o F.hff").status == 0);
    const CommandResult hff = runCommand("cd '" + dir.string() + "' && " + HEMIRAD_BINARY + " formfactors " + scene +
                                         " --samples 256 --threads 1 -o - --format hff --quiet | cat > piped.hff");
    REQUIRE(hff.status == 0);
    CHECK(readText(dir / "piped.hff").size() > 1000);
    CHECK(readText(dir / "piped.hff") == readText(dir / "F.hff"));
    CHECK(runCommand(std::string(HEMIRAD_BINARY) + " info '" + (dir / "piped.hff").string() + "'").status == 0);
    const CommandResult png = runCommand(std::string(HEMIRAD_BINARY) + " render " + scene +
                                         " --samples 256 --size 16x16 -o - --quiet | head -c 8 | od -An -c");
    CHECK(png.output.find("P   N   G") != std::string::npos);

    const std::string log = (dir / "terminal.log").string();
    for (const std::vector<std::string>& arguments :
         {std::vector<std::string>{"formfactors", scene, "-o", "-", "--format", "hff"},
          std::vector<std::string>{"render", scene, "-o", "-"}, std::vector<std::string>{"solve", scene, "-o", "-", "--format", "ply"}}) {
        CAPTURE(arguments[0]);
        CHECK(runOnTerminal(arguments, log) == 1);
        const std::string message = readText(log);
        CHECK(message.find("cannot write binary data to standard output: it is a terminal") != std::string::npos);
        CHECK(message.find("scene:") == std::string::npos);  // refused before the scene was loaded
    }
    // Text goes to a terminal as to any other target.
    CHECK(runOnTerminal({"solve", scene, "--samples", "256", "-o", "-"}, log) == 0);
}

TEST_CASE("Output formats: --format names it for -o -, a FIFO or a device, and a contradiction or an unknown extension is a usage error") {
    const auto dir = tempDir("output-formats");
    const std::string scene = sourcePath("scenes/cornell_box.obj");
    const struct {
        const char* arguments;
        const char* message;
    } refused[] = {
        {"solve SCENE -o B.ply --format csv", "-o B.ply and --format csv disagree"},
        {"solve SCENE -o B.txt", "'solve' -o B.txt: unknown output type '.txt' (use .csv or .ply, or -o - for standard output)"},
        {"formfactors SCENE -o F.txt", "unknown output type '.txt' (use .mtx or .hff"},
        {"solve SCENE -o - --format png", "--format for 'solve' expects csv or ply, got 'png'"},
        {"subdivide SCENE -o - --max-edge 100", "'subdivide' writes an OBJ and its MTL beside it"},
        {"solve SCENE --ff - -o B.csv", "--ff names a file that F is read from or stored in"},
        {"bench SCENE -o - --json -", "-o - and --json - would both write to standard output"},
        {"info SCENE --format csv", "option '--format' does not apply to 'info'"},
    };
    for (const auto& r : refused) {
        std::string arguments = r.arguments;
        arguments.replace(arguments.find("SCENE"), 5, scene);
        CAPTURE(arguments);
        const CommandResult run = runToFiles(dir, arguments);
        CHECK(run.status == 2);
        CHECK(readText(dir / "err.txt").find(r.message) != std::string::npos);
        CHECK(readText(dir / "out.txt").empty());
    }
    CHECK_FALSE(std::filesystem::exists(dir / "F.txt"));
    CHECK_FALSE(std::filesystem::exists(dir / "B.txt"));
    // A FIFO takes --format: PLY through it, the same bytes as the file.
    REQUIRE(runToFiles(dir, "solve " + scene + " --samples 256 --threads 1 -o B.ply").status == 0);
    REQUIRE(::mkfifo((dir / "fifo").c_str(), 0600) == 0);
    const CommandResult fifo = runCommand("cd '" + dir.string() + "' && { timeout 60 cat fifo > fromfifo.ply & } ; " +
                                          HEMIRAD_BINARY + " solve " + scene +
                                          " --samples 256 --threads 1 -o fifo --format ply --quiet; status=$?; wait; "
                                          "exit $status");
    CHECK(fifo.status == 0);
    CHECK(readText(dir / "fromfifo.ply") == readText(dir / "B.ply"));
}
