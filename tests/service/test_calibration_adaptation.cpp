// Coil-by-coil adaptation through the service (docs/model.md §11.6): calibrate's answer pasted
// back as the next fit's `joint_prior` (its parameters as they are, with its correlation) and
// its calibrated_scenario as the next scenario; two coils in sequence end where one fit of both
// ends. And the operational modal observables: the running stand's least-damped root at a speed
// recovers the structure's damping from what a plant records while rolling.

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/calibration_observables.h"
#include "core/speed_limit.h"
#include "core/scenario.h"
#include "core/stability.h"
#include "service/evaluate.h"
#include "support/refused_options.h"
#include "support/approx.h"

using nlohmann::json;
using namespace rollgap;

namespace calibration_adaptation_test {

json calibrate(const json& scenario, const json& options) {
    const service::Outcome outcome = service::evaluate(
        {{"analysis", "calibrate"}, {"scenario", scenario}, {"options", options}});
    REQUIRE_MESSAGE(outcome.ok(), outcome.body.dump());
    return outcome.body;
}

// Force and slip of a synthetic stand (viscosity 6.0e-4 Pa s, asperity factor 0.8) at two speeds
// of a coil, with seeded noise of 0.5 % and 2 %.
json coil_observations(double low, double high, std::uint64_t seed) {
    core::Scenario truth;
    truth.lubricant.viscosity = 6.0e-4;
    truth.friction.asperity_factor = 0.8;
    std::mt19937_64 generator(seed);
    std::normal_distribution<double> normal;
    json out = json::array();
    for (const double v : {low, high}) {
        const core::SteadyFigures bite = core::steady_figures(truth, v);
        REQUIRE(bite.ok);
        const double force_u = 0.005 * bite.force / 1e3, slip_u = 0.02 * bite.forward_slip;
        const json at = {{"rolls", {{"speed_m_per_s", v}}}};
        out.push_back({{"scenario", at},
                       {"quantity", "roll_force_kN"},
                       {"value", bite.force / 1e3 + force_u * normal(generator)},
                       {"standard_uncertainty", force_u}});
        out.push_back({{"scenario", at},
                       {"quantity", "forward_slip"},
                       {"value", bite.forward_slip + slip_u * normal(generator)},
                       {"standard_uncertainty", slip_u}});
    }
    return out;
}

const json parameters = {{{"field", "/lubricant/viscosity_Pa_s"}},
                         {{"field", "/friction/asperity_factor"}}};

}  // namespace calibration_adaptation_test

using namespace calibration_adaptation_test;

TEST_CASE("calibrate: a joint prior is read strictly") {
    const json prior = {
        {"parameters",
         {{{"field", "/lubricant/viscosity_Pa_s"}, {"value", 5.5e-4}, {"standard_error", 1e-5}},
          {{"field", "/friction/asperity_factor"}, {"value", 1.0}, {"standard_error", 0.05}}}},
        {"correlation", {{1, 0.5}, {0.5, 1}}}};
    const json observations = coil_observations(6, 14, 1);
    SUBCASE("every field of the prior must be fitted") {
        test::refused_options("calibrate",
                              {{"parameters", {parameters[0]}},
                               {"observations", observations},
                               {"joint_prior", prior}},
                              "/options/joint_prior/parameters/1/field");
    }
    SUBCASE("one prior per parameter") {
        json own = parameters;
        own[1]["prior"] = {{"value", 1.0}, {"standard_uncertainty", 0.1}};
        test::refused_options(
            "calibrate",
            {{"parameters", own}, {"observations", observations}, {"joint_prior", prior}},
            "/options/parameters/1/prior");
    }
    SUBCASE("a prior needs a positive definite covariance") {
        json singular = prior;
        singular["correlation"] = {{1, 1}, {1, 1}};
        test::refused_options(
            "calibrate",
            {{"parameters", parameters}, {"observations", observations}, {"joint_prior", singular}},
            "/options/joint_prior/correlation");
    }
}

TEST_CASE(
    "calibrate: two coils in sequence, each answer pasted back as the next prior, = one joint fit") {
    const json first = coil_observations(6, 14, 3), second = coil_observations(10, 20, 4);
    const json one =
        calibrate(json::object(), {{"parameters", parameters}, {"observations", first}});
    REQUIRE(one["result"]["status"] == "converged");
    // The answer as it is: calibrated_scenario as the scenario, parameters and correlation as the
    // joint prior (calibrate's other parameter members are accepted and ignored).
    const json prior = {{"parameters", one["result"]["parameters"]},
                        {"correlation", one["result"]["correlation"]}};
    const json two =
        calibrate(one["result"]["calibrated_scenario"],
                  {{"parameters", parameters}, {"observations", second}, {"joint_prior", prior}});
    REQUIRE(two["result"]["status"] == "converged");
    CHECK(two["options"]["joint_prior"]["parameters"].size() == 2);

    json both = first;
    for (const json& o : second) both.push_back(o);
    const json joint =
        calibrate(json::object(), {{"parameters", parameters}, {"observations", both}});
    REQUIRE(joint["result"]["status"] == "converged");
    for (int k = 0; k < 2; ++k) {
        const json& s = two["result"]["parameters"][k];
        const json& j = joint["result"]["parameters"][k];
        CAPTURE(s.dump());
        CAPTURE(j.dump());
        CHECK(s["at_bound"].is_null());  // inside the field's bounds: a real posterior
        CHECK(j["at_bound"].is_null());
        const double se = j["standard_error"].get<double>();
        CHECK(std::abs(s["value"].get<double>() - j["value"].get<double>()) < 0.02 * se);
        CHECK(s["standard_error"].get<double>() == rollgap::test::approx(se).epsilon(0.01));
    }
    // The echo reruns to the same fit.
    const json again = calibrate(two["scenario"], two["options"]);
    CHECK(again["result"]["parameters"] == two["result"]["parameters"]);
}

TEST_CASE("calibrate: the running stand's least-damped root recovers the structure's damping") {
    // The plant: the default stand with a Rayleigh damping ratio of 0.05. What it records while
    // rolling at 15 m/s: the frequency and damping ratio of its least-damped vibration.
    core::Scenario plant;
    plant.structure.rayleigh_damping_ratio = 0.05;
    plant.rolls.speed = 15.0;
    const core::SpeedStability running = core::stability_at(plant);
    REQUIRE(running.steady_status == core::BiteStatus::ok);
    const json at = {{"rolls", {{"speed_m_per_s", 15}}}};
    const json observations = {{{"scenario", at},
                                {"quantity", "running_damping_ratio"},
                                {"value", running.least_damped.damping_ratio},
                                {"standard_uncertainty", 0.002}},
                               {{"scenario", at},
                                {"quantity", "running_frequency_Hz"},
                                {"value", running.least_damped.frequency_Hz},
                                {"standard_uncertainty", 0.5}}};
    const json fit =
        calibrate(json::object(), {{"parameters", {{{"field", "/mill/rayleigh/damping_ratio"}}}},
                                   {"observations", observations}});
    REQUIRE(fit["result"]["status"] == "converged");
    MESSAGE("running root at 15 m/s: " << running.least_damped.frequency_Hz << " Hz, damping ratio "
                                       << running.least_damped.damping_ratio << "; fitted "
                                       << fit["result"]["parameters"][0].dump());
    CHECK(fit["result"]["parameters"][0]["value"].get<double>() ==
          rollgap::test::approx(0.05).epsilon(1e-4));
    CHECK(fit["result"]["observations"][0]["predicted"].get<double>() ==
          rollgap::test::approx(running.least_damped.damping_ratio).epsilon(1e-6));
}
