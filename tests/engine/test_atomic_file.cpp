// AtomicFile (issue 35 #14): a rewrite keeps the file's mode and owner, temporary names are unique
// across hosts sharing a folder, and a hard link keeps the old content (rename semantics).
#include "support.hpp"

#include "engine/atomic_file.hpp"
#include "engine/error.hpp"

#include <doctest/doctest.h>

#include <climits>
#include <sys/stat.h>
#include <unistd.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

struct stat statOf(const std::string& path) {
    struct stat st {};
    REQUIRE(::stat(path.c_str(), &st) == 0);
    return st;
}

void rewrite(const std::string& path, const std::string& text) {
    AtomicFile file(path, false);
    file.stream() << text;
    file.commit();
}

std::string hostName() {
    char name[HOST_NAME_MAX + 1] = {};
    REQUIRE(::gethostname(name, sizeof name) == 0);
    return name;
}

}  // namespace

TEST_CASE("Rewriting a file keeps its permission bits: a 600 file stays 600, whatever the umask") {
    const auto dir = tempDir("atomic-mode");
    for (mode_t mode : {0600, 0640, 0664, 0751, 0444 | 0200}) {
        CAPTURE(mode);
        const std::string path = writeFile(dir / "F.mtx", "old\n");
        REQUIRE(::chmod(path.c_str(), mode) == 0);
        rewrite(path, "new\n");
        CHECK(readText(path) == "new\n");
        CHECK((statOf(path).st_mode & 07777) == mode);
        std::filesystem::remove(path);
    }
    // A new file gets the usual mode (0666 less the umask).
    const mode_t mask = ::umask(022);
    rewrite((dir / "fresh.csv").string(), "x\n");
    ::umask(mask);
    CHECK((statOf((dir / "fresh.csv").string()).st_mode & 07777) == 0644);
}

TEST_CASE("Rewriting a file keeps its owner and group when the process may set them") {
    const auto dir = tempDir("atomic-owner");
    const std::string path = writeFile(dir / "B.csv", "old\n");
    // As root the file is given to nobody first; as anyone else it is already the process's own.
    const uid_t uid = ::geteuid() == 0 ? 65534 : ::geteuid();
    const gid_t gid = ::geteuid() == 0 ? 65534 : ::getegid();
    REQUIRE(::chown(path.c_str(), uid, gid) == 0);
    rewrite(path, "new\n");
    CHECK(statOf(path).st_uid == uid);
    CHECK(statOf(path).st_gid == gid);
}

TEST_CASE("Temporary names hold the target's name, the host name and the process, and never repeat") {
    const auto dir = tempDir("atomic-names");
    const std::string target = (dir / "F.shard-0-of-2.hff").string();
    const std::string host = hostName();
    AtomicFile a(target), b(target);
    const std::filesystem::path ta(a.temporaryPath()), tb(b.temporaryPath());
    CHECK(ta != tb);
    CHECK(ta.parent_path() == dir);
    for (const std::string& name : {ta.filename().string(), tb.filename().string()}) {
        CAPTURE(name);
        CHECK(name.find("F.shard-0-of-2.hff") != std::string::npos);
        CHECK(name.find(host) != std::string::npos);
        CHECK(name.find("." + std::to_string(::getpid()) + ".") != std::string::npos);
        CHECK(name.find("hemirad-tmp") != std::string::npos);
        CHECK(name[0] == '.');  // hidden
    }
    // A 250-byte target name is shortened in its temporary name, which still fits a folder entry.
    const std::string longName = std::string(120, 'n') + std::string(60, 'x') + "光光光光光光光光光光.hff";
    REQUIRE(longName.size() <= 250);
    AtomicFile c((dir / longName).string());
    const std::string temp = std::filesystem::path(c.temporaryPath()).filename().string();
    CHECK(temp.size() <= NAME_MAX);
    CHECK(temp.find(host) != std::string::npos);
    CHECK(temp.find(std::string(40, 'n')) != std::string::npos);
    c.stream() << "long";
    c.commit();
    CHECK(readText(dir / longName) == "long");
}

TEST_CASE("Rewriting a hard-linked file replaces that name only: the other link keeps the old content") {
    // Rename semantics, documented in atomic_file.hpp and the README: the new file is a new inode.
    const auto dir = tempDir("atomic-links");
    const std::string path = writeFile(dir / "F.mtx", "old\n");
    REQUIRE(::link(path.c_str(), (dir / "backup.mtx").c_str()) == 0);
    rewrite(path, "new\n");
    CHECK(readText(path) == "new\n");
    CHECK(readText(dir / "backup.mtx") == "old\n");
    CHECK(statOf(path).st_nlink == 1);
}
