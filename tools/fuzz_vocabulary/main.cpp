// fuzz_vocabulary [FUZZ_DIR]: writes fuzz/fuzz_evaluate.dict and the generated seeds of
// fuzz/corpus/fuzz_evaluate/ (vocabulary.h) into FUZZ_DIR (default: ./fuzz). Run it after adding
// an analysis, a scenario field or an option; a test fails until the files are up to date.

#include <filesystem>
#include <fstream>
#include <iostream>

#include "tools/fuzz_vocabulary/vocabulary.h"

int main(int argc, char** argv) {
    const std::filesystem::path fuzz = argc > 1 ? argv[1] : "fuzz";
    if (!std::filesystem::is_directory(fuzz / "corpus/fuzz_evaluate")) {
        std::cerr << "fuzz_vocabulary: no " << (fuzz / "corpus/fuzz_evaluate").string()
                  << ": give the repository's fuzz/ directory\n";
        return 2;
    }
    const auto write = [](const std::filesystem::path& path, const std::string& text) {
        std::ofstream out(path, std::ios::binary);
        out << text;
        std::cout << path.string() << '\n';
        return static_cast<bool>(out);
    };
    bool ok = write(fuzz / "fuzz_evaluate.dict", rollgap::tools::fuzz_evaluate_dictionary());
    for (const auto& [name, text] : rollgap::tools::fuzz_evaluate_seeds())
        ok = write(fuzz / "corpus/fuzz_evaluate" / name, text) && ok;
    return ok ? 0 : 1;
}
