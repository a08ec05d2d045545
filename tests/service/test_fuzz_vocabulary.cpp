// The fuzz_evaluate harness's dictionary and generated seeds (tools/fuzz_vocabulary) as
// committed in fuzz/ are what the analysis rows, the scenario field table and the OpenAPI
// options give today: a new analysis, field or option fails here until
// `build/tools/fuzz_vocabulary fuzz` is run. And every analysis, plus "base", is in both.

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <string_view>

#include "service/analyses/table.h"
#include "support/repository.h"
#include "tools/fuzz_vocabulary/vocabulary.h"

using namespace rollgap;

TEST_CASE("the committed fuzz dictionary and seeds are the generated ones") {
    const std::filesystem::path fuzz = test::repository_root() / "fuzz";
    CHECK_MESSAGE(test::read_text(fuzz / "fuzz_evaluate.dict") == tools::fuzz_evaluate_dictionary(),
                  "run build/tools/fuzz_vocabulary fuzz");
    for (const auto& seed : tools::fuzz_evaluate_seeds()) {
        const auto& name = seed.first;  // not a structured binding: clang 14 cannot CAPTURE one
        CAPTURE(name);
        CHECK_MESSAGE(test::read_text(fuzz / "corpus/fuzz_evaluate" / name) == seed.second,
                      "run build/tools/fuzz_vocabulary fuzz");
    }
}

TEST_CASE("the fuzz dictionary and corpus know every analysis and base") {
    const std::string dictionary = tools::fuzz_evaluate_dictionary();
    std::string corpus;
    for (const auto& [name, text] : tools::fuzz_evaluate_seeds()) corpus += text;
    for (const service::Analysis& analysis : service::analyses()) {
        CAPTURE(analysis.name);
        CHECK(dictionary.find(test::joined({"=\"", analysis.name, "\"\n"})) != std::string::npos);
        CHECK(corpus.find(test::joined({"\"analysis\":\"", analysis.name, "\""})) !=
              std::string::npos);
    }
    CHECK(dictionary.find("=\"base\"\n") != std::string::npos);
    CHECK(corpus.find("\"base\":") != std::string::npos);
}
