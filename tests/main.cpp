// The test runners' main: doctest's, with one guard. ctest runs each test case by name
// (--test-case=NAME, from doctest_discover_tests); a name the filter cannot match (CMake cuts a
// name at a ';') would select nothing and pass without running a single check. Here a run whose
// --test-case filter selects no test case fails, so no test is ever skipped silently.

#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdio>
#include <cstring>

namespace {

// Test cases that passed the filters in the last run (doctest's own count).
unsigned selected = 0;

struct SelectionListener : doctest::IReporter {
    explicit SelectionListener(const doctest::ContextOptions&) {}
    void report_query(const doctest::QueryData&) override {}
    void test_run_start() override {}
    void test_run_end(const doctest::TestRunStats& stats) override {
        selected = stats.numTestCasesPassingFilters;
    }
    void test_case_start(const doctest::TestCaseData&) override {}
    void test_case_reenter(const doctest::TestCaseData&) override {}
    void test_case_end(const doctest::CurrentTestCaseStats&) override {}
    void test_case_exception(const doctest::TestCaseException&) override {}
    void subcase_start(const doctest::SubcaseSignature&) override {}
    void subcase_end() override {}
    void log_assert(const doctest::AssertData&) override {}
    void log_message(const doctest::MessageData&) override {}
    void test_case_skipped(const doctest::TestCaseData&) override {}
};

}  // namespace

REGISTER_LISTENER("selection", 1, SelectionListener);

int main(int argc, char** argv) {
    doctest::Context context(argc, argv);
    const int result = context.run();
    if (context.shouldExit()) return result;  // a query (--list-test-cases, --help)
    bool filtered = false;
    for (int i = 1; i < argc; ++i) {
        filtered = filtered || std::strncmp(argv[i], "--test-case=", 12) == 0 ||
                   std::strncmp(argv[i], "-tc=", 4) == 0;
    }
    if (filtered && selected == 0) {
        std::fprintf(stderr,
                     "no test case matches the --test-case filter: nothing ran (a name with a "
                     "';' is cut by CMake; write ',' instead)\n");
        return 1;
    }
    return result;
}
