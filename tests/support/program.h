#pragma once
// The `rollgap` program of this build, for tests that run it as a separate process: the test
// runner is build/tests/rollgap_tests, the program build/rollgap (tests/CMakeLists.txt makes
// the runner depend on it, so it is always there; a missing one fails the test, never skips it).

#include <filesystem>

#include <doctest/doctest.h>

namespace rollgap::test {

inline std::filesystem::path rollgap_program() {
    const std::filesystem::path program =
        std::filesystem::canonical("/proc/self/exe").parent_path().parent_path() / "rollgap";
    REQUIRE_MESSAGE(std::filesystem::exists(program),
                    "no " << program.string() << " next to the tests (build the rollgap target)");
    return program;
}

}  // namespace rollgap::test
