#pragma once
// Request text → JSON, with the limits a service needs on client input: bounded nesting
// (the code that walks JSON afterwards recurses), no duplicate keys (the last one would
// silently win), numbers that fit a double (1e999 is not infinity here).

#include <string_view>
#include <variant>

#include <nlohmann/json.hpp>

#include "api/problem.h"

namespace rollgap::api {

// The scenario is 4 levels deep; 64 leaves room for any future request while keeping
// every recursive walk far from the stack limit.
inline constexpr int max_json_depth = 64;

// The JSON value, or an `invalid_json` problem saying what is wrong and where.
std::variant<nlohmann::json, Problem> parse_json_text(std::string_view text);

// Whether a JSON value (e.g. built in code) nests deeper than `max_depth` containers.
// Iterative, so it is safe on any depth.
bool nests_deeper_than(const nlohmann::json& value, int max_depth);

}  // namespace rollgap::api
