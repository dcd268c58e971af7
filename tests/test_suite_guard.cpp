// The suite's own guard: every doctest case is exactly one ctest entry. A case name that CMake's test
// discovery splits (a ';') became entries that matched no case and "passed" without running; this
// case compares ctest's discovered entries (label doctest; the pytest suite is one entry labelled
// python) with doctest's own count (tests/main.cpp also fails an entry whose filter matches no case).
#include <doctest/doctest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>

namespace {

std::string capture(const std::string& command) {
    std::string output;
    FILE* pipe = ::popen(command.c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::array<char, 4096> buffer;
    std::size_t n;
    while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) output.append(buffer.data(), n);
    CHECK(::pclose(pipe) == 0);
    return output;
}

}  // namespace

TEST_CASE("Every doctest case is exactly one ctest entry, so no case is skipped unseen") {
    const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
    const std::string count = capture("'" + self + "' --count 2>&1");
    std::smatch m;
    REQUIRE(std::regex_search(count, m, std::regex("current filters: ([0-9]+)")));
    const long cases = std::stol(m[1]);
    const std::string listing =
        capture("cd '" + std::string(HEMIRAD_TESTS_BUILD_DIR) + "' && '" + std::string(HEMIRAD_CTEST) + "' -N -L '^doctest$' 2>&1");
    const std::regex entry("Test +#[0-9]+: ");
    long entries = 0;
    for (std::sregex_iterator it(listing.begin(), listing.end(), entry), end; it != end; ++it) ++entries;
    CAPTURE(listing);
    CHECK(cases > 100);
    CHECK(entries == cases);
}
