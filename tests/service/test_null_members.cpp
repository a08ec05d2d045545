// The contract "absent or null: the defaults" kept by the readers, not only by the document:
// a sweep's critical_speed and amplitude, a map's and a mill sweep's critical_speed, evaluate's
// nested runs, a calibration observation's scenario and a parameter's prior each give, as null,
// exactly the answer they give absent; and every analysis takes its own echo back (the answer's
// scenario and options rerun to the same answer), calibrate's with its nulls included.

#include <doctest/doctest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "service/evaluate.h"

using nlohmann::json;
using namespace rollgap;

namespace null_members_test {

json answer(const json& request) {
    const service::Outcome outcome = service::evaluate(request);
    CAPTURE(outcome.body.dump().substr(0, 600));
    REQUIRE(outcome.ok());
    return outcome.body;
}

// The request with `member` of its options set to null answers as the request without it.
void null_is_absent(json request, const std::string& member) {
    CAPTURE(request["analysis"]);
    CAPTURE(member);
    const json without = answer(request);
    request["options"][member] = nullptr;
    CHECK(answer(request) == without);
}

const json two_stands = {{"entry_thickness_mm", 2.25},
                         {"exit_thickness_mm", {1.88, 1.6}},
                         {"spans", {{"length_m", {5}}, {"tension_MPa", {60}}}},
                         {"stands", {json::object(), json::object()}}};

}  // namespace null_members_test

namespace nmt = null_members_test;

TEST_CASE("null members: a nested options object given as null is its defaults") {
    const json viscosity = {{"parameter", "/lubricant/viscosity_Pa_s"}, {"values", {4e-4, 7e-4}}};
    json sweep = {{"analysis", "sweep"}, {"options", viscosity}};
    sweep["options"]["critical_speed"] = {{"speed_step_m_per_s", 0.5}};
    nmt::null_is_absent(sweep, "amplitude");  // the other quantity's member, as an echo has it
    sweep["options"].erase("critical_speed");
    nmt::null_is_absent(sweep, "critical_speed");
    json amplitude = {
        {"analysis", "sweep"},
        {"options",
         {{"parameter", "/rolls/speed_m_per_s"}, {"values", {10, 12}}, {"quantity", "amplitude"}}}};
    nmt::null_is_absent(amplitude, "amplitude");
    nmt::null_is_absent(amplitude, "critical_speed");
    const json map = {
        {"analysis", "map"},
        {"options",
         {{"parameters",
           {{{"parameter", "/strip/reduction"}, {"values", {0.2}}},
            {{"parameter", "/lubricant/viscosity_Pa_s"}, {"values", {5e-4, 8e-4}}}}}}}};
    nmt::null_is_absent(map, "critical_speed");
    const json evaluate = {{"analysis", "evaluate"}, {"options", {{"detail", "summary"}}}};
    nmt::null_is_absent(evaluate, "critical_speed");
    nmt::null_is_absent(evaluate, "amplitude");
    const json mill_sweep = {
        {"analysis", "tandem_sweep"},
        {"tandem", nmt::two_stands},
        {"options",
         {{"parameter", "/speed_m_per_s"}, {"values", {10, 12}}, {"quantity", "stability"}}}};
    nmt::null_is_absent(mill_sweep, "critical_speed");
}

TEST_CASE("null members: a calibration's observation scenario and prior as null, and its echo") {
    const json observations = {
        {{"quantity", "roll_force_kN"}, {"value", 9000}, {"standard_uncertainty", 60}},
        {{"scenario", {{"strip", {{"reduction", 0.3}}}}},
         {"quantity", "roll_force_kN"},
         {"value", 11000},
         {"standard_uncertainty", 80}}};
    const json request = {{"analysis", "calibrate"},
                          {"options",
                           {{"parameters", {{{"field", "/strip/flow_stress_MPa"}}}},
                            {"observations", observations}}}};
    const json fitted = nmt::answer(request);
    json with_nulls = request;
    with_nulls["options"]["observations"][0]["scenario"] = nullptr;
    with_nulls["options"]["parameters"][0]["prior"] = nullptr;
    with_nulls["options"]["joint_prior"] = nullptr;
    CHECK(nmt::answer(with_nulls) == fitted);
    // The answer echoes a parameter without prior as "prior": null; sent back, it is the same fit.
    REQUIRE(fitted["options"]["parameters"][0]["prior"].is_null());
    const json echoed = {{"analysis", "calibrate"},
                         {"scenario", fitted["scenario"]},
                         {"options", fitted["options"]}};
    CHECK(nmt::answer(echoed) == fitted);
}

TEST_CASE("null members: every stand analysis and mill analysis reruns from its own echo") {
    const json two_stands = nmt::two_stands;
    for (const json& request : {
             json{{"analysis", "roll_gap"}, {"options", {{"distributions", false}}}},
             json{{"analysis", "stability"}, {"options", {{"detail", "summary"}}}},
             json{{"analysis", "tension_cycle"}},
             json{{"analysis", "evaluate"}, {"options", {{"detail", "summary"}}}},
             json{{"analysis", "speed_limit"}, {"options", {{"max_roll_force_kN", 12000}}}},
             json{{"analysis", "tandem"}, {"tandem", two_stands}},
         }) {
        CAPTURE(request["analysis"]);
        const json first = nmt::answer(request);
        const char* subject = first.contains("tandem") ? "tandem" : "scenario";
        const json echoed = {{"analysis", first["analysis"]},
                             {subject, first[subject]},
                             {"options", first["options"]}};
        CHECK(nmt::answer(echoed) == first);
    }
}
