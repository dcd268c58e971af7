// Doctest entry point: every run works in its own temporary directory (TMPDIR, HOME and the XDG
// folders point into it, so neither /tmp nor the user's home gain files), removed at exit; a run that
// was asked for test cases by name (as ctest runs each entry) and ran none fails.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "engine/threads.hpp"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

namespace {

std::atomic<int> g_casesStarted{0};

/// Counts the test cases that really start (subcases re-enter a case; only the first entry counts).
struct CaseCounter : doctest::IReporter {
    explicit CaseCounter(const doctest::ContextOptions&) {}
    void report_query(const doctest::QueryData&) override {}
    void test_run_start() override {}
    void test_run_end(const doctest::TestRunStats&) override {}
    void test_case_start(const doctest::TestCaseData&) override { ++g_casesStarted; }
    void test_case_reenter(const doctest::TestCaseData&) override {}
    void test_case_end(const doctest::CurrentTestCaseStats&) override {}
    void test_case_exception(const doctest::TestCaseException&) override {}
    void subcase_start(const doctest::SubcaseSignature&) override {}
    void subcase_end() override {}
    void log_assert(const doctest::AssertData&) override {}
    void log_message(const doctest::MessageData&) override {}
    void test_case_skipped(const doctest::TestCaseData&) override {}
};
REGISTER_LISTENER("hemirad-case-counter", 1, CaseCounter);

/// A private directory for this run's files, under the caller's TMPDIR (default /tmp).
std::filesystem::path makeRunDirectory() {
    const char* base = std::getenv("TMPDIR");
    std::string pattern = std::string(base && *base ? base : "/tmp") + "/hemirad-tests-XXXXXX";
    if (!::mkdtemp(pattern.data())) {
        std::perror("hemirad_tests: mkdtemp");
        std::exit(2);
    }
    return pattern;
}

bool selectsTestCases(int argc, char** argv) {
    for (int k = 1; k < argc; ++k) {
        const std::string arg = argv[k];
        if (arg.rfind("--test-case=", 0) == 0 || arg.rfind("-tc=", 0) == 0) return true;
    }
    return false;
}

}  // namespace

int main(int argc, char** argv) {
    const std::filesystem::path run = makeRunDirectory();
    const std::filesystem::path home = run / "home";
    std::filesystem::create_directories(home / ".config");
    std::filesystem::create_directories(home / ".cache");
    // Set before any test (or thread) starts; child processes inherit them.
    ::setenv("TMPDIR", run.c_str(), 1);
    ::setenv("HOME", home.c_str(), 1);
    ::setenv("XDG_CONFIG_HOME", (home / ".config").c_str(), 1);
    ::setenv("XDG_CACHE_HOME", (home / ".cache").c_str(), 1);
    hemirad::configureProcessThreads(0);

    doctest::Context context(argc, argv);
    int status = context.run();
    if (status == 0 && !context.shouldExit() && selectsTestCases(argc, argv) && g_casesStarted == 0) {
        std::fprintf(stderr, "hemirad_tests: the --test-case filter matched no test case (a name with a "
                             "character ctest or doctest splits on?)\n");
        status = 1;
    }
    std::error_code ignored;
    std::filesystem::remove_all(run, ignored);
    return status;
}
