#pragma once
// The repository's root, for tests that read its files (the documentation's examples, the
// fixtures, deploy/): tests/CMakeLists.txt defines ROLLGAP_SOURCE_DIR, so a test runner finds
// them from whatever directory it is started in.

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <string_view>

namespace rollgap::test {

inline std::filesystem::path repository_root() { return ROLLGAP_SOURCE_DIR; }

// A file's whole text (empty when it cannot be read: the comparison that follows fails).
inline std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// Text pieces joined (GCC 12 warns falsely on "literal" + std::string at -O3).
inline std::string joined(std::initializer_list<std::string_view> pieces) {
    std::string text;
    for (const std::string_view piece : pieces) text.append(piece);
    return text;
}

}  // namespace rollgap::test
