#pragma once
// What the tests of the mill's analyses share (the suite is compiled as unity batches, so a
// helper copied into two test files is a redefinition): a request's answer or its refusal
// through the one facade, and the small mill they use.

#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include "service/evaluate.h"

namespace rollgap::test {

// The answer to `request`, which must succeed.
inline nlohmann::json answer_of(const nlohmann::json& request) {
    const service::Outcome outcome = service::evaluate(request);
    CAPTURE(outcome.body.dump().substr(0, 600));
    REQUIRE(outcome.ok());
    return outcome.body;
}

// The problem answering `request`, which must be a 422.
inline nlohmann::json refusal_of(const nlohmann::json& request) {
    const service::Outcome outcome = service::evaluate(request);
    CAPTURE(outcome.body.dump().substr(0, 600));
    REQUIRE(outcome.http_status == 422);
    return outcome.body;
}

// A two-stand mill: stands 4 and 5 of the default schedule (1.88 → 1.6 → 1.36 mm), one 5 m span
// at 60 MPa; its critical speeds take ~0.1 s.
inline const nlohmann::json two_stands = {
    {"entry_thickness_mm", 1.88},
    {"exit_thickness_mm", {1.6, 1.36}},
    {"spans", {{"length_m", {5}}, {"tension_MPa", {60}}}},
    {"stands", nlohmann::json::array({nlohmann::json::object(), nlohmann::json::object()})}};

}  // namespace rollgap::test
