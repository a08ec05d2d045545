#pragma once
// The repository's root, for tests that read its files (the documentation's examples, the
// fixtures, deploy/): tests/CMakeLists.txt defines ROLLGAP_SOURCE_DIR, so a test runner finds
// them from whatever directory it is started in.

#include <filesystem>

namespace rollgap::test {

inline std::filesystem::path repository_root() { return ROLLGAP_SOURCE_DIR; }

}  // namespace rollgap::test
