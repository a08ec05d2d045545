// The plant limits' ends carried through a calibration posterior (docs/model.md §13.2): the
// window's rule (core::bound_window) on made-up ends whose answer is known, and through the
// facade the σ of a force limit's lower end and a power limit's upper end against central
// differences of the whole analysis — the speed limit run again, without a posterior, on the
// stand moved by one standard error of each parameter, its ends found by its own grid and
// bisection, not by the local root the propagation uses.

#include <doctest/doctest.h>

#include <cmath>
#include <optional>

#include <nlohmann/json.hpp>

#include "core/propagation.h"
#include "core/speed_limit.h"
#include "service/evaluate.h"
#include "support/approx.h"

using nlohmann::json;
using namespace rollgap;

namespace speed_limit_bounds_test {

core::LimitAnswer end_of(core::SpeedLimitKind kind, std::optional<double> lower,
                         std::optional<double> upper, std::optional<double> lower_sd,
                         std::optional<double> upper_sd) {
    core::LimitAnswer a;
    a.kind = kind;
    a.lower_speed = lower;
    a.upper_speed = upper;
    a.lower_speed_sd = lower_sd;
    a.upper_speed_sd = upper_sd;
    return a;
}

// A window [17, 24] m/s: the force bounds it below (sd 0.5 m/s), chatter above (its bound
// taken already), the power allows 25 m/s (sd `power_sd`).
core::SpeedLimitResult made_up(double power_sd, double force_sd = 0.5) {
    core::SpeedLimitResult r;
    r.status = core::SpeedLimitStatus::ok;
    r.operating_speed = 19.0;
    r.window_min = 17.0;
    r.window_max = 24.0;
    r.advised_speed = 24.0;
    r.binding_min = core::SpeedLimitKind::force;
    r.binding_max = core::SpeedLimitKind::chatter;
    r.operating_permitted = true;
    r.limits = {end_of(core::SpeedLimitKind::steady_state, {}, {}, {}, {}),
                end_of(core::SpeedLimitKind::force, 17.0, {}, force_sd, {}),
                end_of(core::SpeedLimitKind::power, {}, 25.0, {}, power_sd),
                end_of(core::SpeedLimitKind::chatter, {}, 24.0, {}, {})};
    return r;
}

json speed_limit(const json& scenario, const json& options) {
    const service::Outcome outcome = service::evaluate(
        {{"analysis", "speed_limit"}, {"scenario", scenario}, {"options", options}});
    REQUIRE_MESSAGE(outcome.ok(), outcome.body.dump().substr(0, 600));
    return outcome.body["result"];
}

const json& limit_row(const json& result, const char* name) {
    for (const json& row : result["limits"])
        if (row["limit"] == name) return row;
    FAIL("no limit ", name);
    return result;
}

}  // namespace speed_limit_bounds_test

using namespace speed_limit_bounds_test;

TEST_CASE("speed limit bounds: every end at its one-sided bound, the tightest binding") {
    const double z = core::normal_quantile(0.95);
    // the power's bound 25 - z 0.5 = 24.18 stays above chatter's 24: chatter binds
    core::SpeedLimitResult r = made_up(0.5);
    core::bound_window(r, z);
    REQUIRE(r.status == core::SpeedLimitStatus::ok);
    CHECK(r.window_max == 24.0);
    CHECK(r.binding_max == core::SpeedLimitKind::chatter);
    CHECK(r.window_min == rollgap::test::approx(17.0 + z * 0.5).epsilon(1e-15));
    CHECK(r.binding_min == core::SpeedLimitKind::force);
    CHECK(r.advised_speed == r.window_max);
    // sd 1 m/s: 25 - z = 23.36 is below 24: the power binds at its bound
    r = made_up(1.0);
    core::bound_window(r, z);
    CHECK(r.window_max == rollgap::test::approx(25.0 - z).epsilon(1e-15));
    CHECK(r.binding_max == core::SpeedLimitKind::power);
    CHECK(r.advised_speed == r.window_max);
    CHECK(r.operating_permitted);
    // the force's bound above the operating speed: not permitted there
    r = made_up(1.0, 1.5);
    core::bound_window(r, z);
    CHECK(r.window_min == rollgap::test::approx(17.0 + 1.5 * z).epsilon(1e-15));
    CHECK_FALSE(r.operating_permitted);
    // bounds that cross: no window is left
    r = made_up(1.0, 4.0);
    core::bound_window(r, z);
    CHECK(r.status == core::SpeedLimitStatus::no_window);
    CHECK_FALSE(r.operating_permitted);
    // without standard deviations nothing moves
    r = made_up(0.0, 0.0);
    core::bound_window(r, z);
    CHECK(r.window_min == 17.0);
    CHECK(r.window_max == 24.0);
    CHECK(r.binding_max == core::SpeedLimitKind::chatter);
}

TEST_CASE("speed limit bounds: a force and a power end's sigma equal differences of the analysis") {
    // the default stand with an asperity factor of 0.7 (1, the default, is the field's bound)
    core::Scenario s;
    s.friction.asperity_factor = 0.7;
    const json stand = {{"friction", {{"asperity_factor", 0.7}}}};
    const core::SteadyFigures at = core::steady_figures(s, s.rolls.speed);
    REQUIRE(at.ok);
    // the force 2 % above today's bounds the speed below, the power 30 % above bounds it above
    const json limits = {{"max_roll_force_kN", 1.02 * at.force / 1e3},
                         {"max_power_kW", 1.3 * at.power / 1e3},
                         {"chatter", false},
                         {"what_to_change", false}};
    // viscosity ±2 %, asperity factor ±3 %, correlation -0.5 (what a fit of force and slip leaves)
    const double se[2] = {0.02 * s.lubricant.viscosity, 0.03 * s.friction.asperity_factor};
    const double rho = -0.5;
    json with_posterior = limits;
    with_posterior["posterior"] = {{"parameters",
                                    {{{"field", "/lubricant/viscosity_Pa_s"},
                                      {"value", s.lubricant.viscosity},
                                      {"standard_error", se[0]}},
                                     {{"field", "/friction/asperity_factor"},
                                      {"value", s.friction.asperity_factor},
                                      {"standard_error", se[1]}}}},
                                   {"correlation", {{1.0, rho}, {rho, 1.0}}}};
    const json result = speed_limit(stand, with_posterior);
    const json& force = limit_row(result, "force");
    const json& power = limit_row(result, "power");
    REQUIRE(force["lower_speed_sd_m_per_s"].is_number());
    REQUIRE(power["upper_speed_sd_m_per_s"].is_number());
    CHECK(force["upper_speed_sd_m_per_s"].is_null());
    CHECK(power["lower_speed_sd_m_per_s"].is_null());

    // each end at the stand moved by ± one standard error of one parameter, by the analysis
    const auto ends = [&](int j, double sign) {
        json patch = stand;
        if (j == 0) patch["lubricant"]["viscosity_Pa_s"] = s.lubricant.viscosity + sign * se[0];
        else patch["friction"]["asperity_factor"] = s.friction.asperity_factor + sign * se[1];
        const json r = speed_limit(patch, limits);
        return std::pair{limit_row(r, "force")["lower_speed_m_per_s"].get<double>(),
                         limit_row(r, "power")["upper_speed_m_per_s"].get<double>()};
    };
    double g_force[2], g_power[2];
    for (int j = 0; j < 2; ++j) {
        const auto [force_up, power_up] = ends(j, 1.0);
        const auto [force_down, power_down] = ends(j, -1.0);
        g_force[j] = (force_up - force_down) / (2.0 * se[j]);
        g_power[j] = (power_up - power_down) / (2.0 * se[j]);
    }
    const auto sigma = [&](const double* g) {
        const double a = g[0] * se[0], b = g[1] * se[1];
        return std::sqrt(a * a + b * b + 2.0 * rho * a * b);
    };
    const double sd_force = force["lower_speed_sd_m_per_s"].get<double>();
    const double sd_power = power["upper_speed_sd_m_per_s"].get<double>();
    MESSAGE("force end: sd " << sd_force << " m/s against " << sigma(g_force) << "; power end: sd "
                             << sd_power << " m/s against " << sigma(g_power));
    CHECK(sd_force > 0.0);
    CHECK(sd_power > 0.0);
    CHECK(sd_force == rollgap::test::approx(sigma(g_force)).epsilon(1e-6));
    CHECK(sd_power == rollgap::test::approx(sigma(g_power)).epsilon(1e-6));

    // the window takes both ends at their bounds
    const double z = core::normal_quantile(0.95);
    const double lower = force["lower_speed_m_per_s"].get<double>();
    const double upper = power["upper_speed_m_per_s"].get<double>();
    CHECK(result["window_min_m_per_s"].get<double>() ==
          rollgap::test::approx(lower + z * sd_force).epsilon(1e-12));
    CHECK(result["window_max_m_per_s"].get<double>() ==
          rollgap::test::approx(upper - z * sd_power).epsilon(1e-12));
    CHECK(result["advised_speed_m_per_s"] == result["window_max_m_per_s"]);
    CHECK(result["binding_limit"] == "power");
    CHECK(result["binding_min"] == "force");
    // and the ends themselves are the posterior mean's, as without a posterior
    const json plain = speed_limit(stand, limits);
    CHECK(limit_row(plain, "force")["lower_speed_m_per_s"] == force["lower_speed_m_per_s"]);
    CHECK(plain["window_min_m_per_s"] == force["lower_speed_m_per_s"]);
}
