#pragma once
// The fuzz_evaluate harness's dictionary and seed requests, derived from the analysis descriptor
// (service/analyses/analysis.h), the scenario field table and the OpenAPI options components,
// so that they know every analysis, field, option and choice the service does. tools/
// fuzz_vocabulary writes them into fuzz/; tests/service/test_fuzz_vocabulary.cpp checks that
// what is committed is what this generates.

#include <string>
#include <utility>
#include <vector>

namespace rollgap::tools {

// fuzz/fuzz_evaluate.dict (libFuzzer's dictionary format).
std::string fuzz_evaluate_dictionary();

// The generated seeds of fuzz/corpus/fuzz_evaluate/: {file name, content}: one request per
// analysis with the least options it accepts, and one on a stored scenario ("base").
std::vector<std::pair<std::string, std::string>> fuzz_evaluate_seeds();

}  // namespace rollgap::tools
