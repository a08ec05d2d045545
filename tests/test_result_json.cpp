// Roll-bite result → JSON: units in the names, columnar distributions, statuses as values.

#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "api/result_json.h"

using nlohmann::json;
using namespace rollgap;

namespace {

core::BitePoint point(double x, double pressure, core::Regime regime) {
    return {x, pressure, -1e6, 2e-6, 1.0, 0.3, 18.0, 1.5e-3, regime};
}

}  // namespace

TEST_CASE("a solved bite is written in engineering units with columnar distributions") {
    core::BiteResult result;
    result.status = core::BiteStatus::ok;
    result.message = "ok";
    result.force = 6.5e6;
    result.torque = 3.3e4;
    result.neutral_point = 2.9e-3;
    result.contact_length = 8.2e-3;
    result.inlet_film = 3.4e-6;
    result.entry_speed = 16.5;
    result.forward_slip = 0.02;
    result.distribution = {point(0.0, 362e6, core::Regime::mixed), point(1e-3, 400e6, core::Regime::boundary),
                           point(8.2e-3, 362e6, core::Regime::full_film)};
    const json body = api::bite_result_json(result);
    CHECK(body["status"] == "ok");
    CHECK(body["force_kN"] == 6500.0);
    CHECK(body["torque_kN_m"] == 33.0);
    CHECK(body["neutral_point_mm"] == 2.9);
    CHECK(body["contact_length_mm"] == 8.2);
    CHECK(body["inlet_film_um"] == 3.4);
    CHECK(body["entry_speed_m_per_s"] == 16.5);
    CHECK(body["forward_slip"] == 0.02);
    CHECK_FALSE(body.contains("skidding"));

    const json& distribution = body["distribution"];
    for (const char* column : {"x_mm", "pressure_MPa", "friction_MPa", "film_um", "film_ratio", "contact_ratio",
                               "strip_speed_m_per_s", "thickness_mm", "regime"}) {
        CAPTURE(column);
        REQUIRE(distribution.contains(column));
        CHECK(distribution[column].size() == 3);
    }
    CHECK(distribution["x_mm"] == json::array({0.0, 1.0, 8.2}));
    CHECK(distribution["pressure_MPa"] == json::array({362.0, 400.0, 362.0}));
    CHECK(distribution["friction_MPa"][0] == -1.0);
    CHECK(distribution["film_um"][0] == 2.0);
    CHECK(distribution["thickness_mm"][0] == 1.5);
    CHECK(distribution["regime"] == json::array({"mixed", "boundary", "full_film"}));
}

TEST_CASE("skidding is a result with its details, not an error") {
    core::BiteResult result;
    result.status = core::BiteStatus::skidding;
    result.message = "no neutral point";
    result.skid_at_exit = true;
    result.skid_residual = -2.5e6;
    result.contact_length = 8.2e-3;
    result.inlet_angle = 0.03;
    const json body = api::bite_result_json(result);
    CHECK(body["status"] == "skidding");
    CHECK(body["message"] == "no neutral point");
    CHECK(body["skidding"]["neutral_point_left_at"] == "exit");
    CHECK(body["skidding"]["residual_MPa"] == -2.5);
    CHECK_FALSE(body.contains("distribution"));
    // No steady state: no force, speeds or film, rather than core's placeholder zeros.
    for (const char* unsolved : {"force_kN", "torque_kN_m", "neutral_point_mm", "entry_speed_m_per_s",
                                 "exit_speed_m_per_s", "forward_slip", "inlet_film_um", "mean_friction_coefficient"}) {
        CAPTURE(unsolved);
        CHECK(body[unsolved].is_null());
    }
    CHECK(body["contact_length_mm"] == 8.2);
    CHECK(body["inlet_angle_rad"] == 0.03);
}

TEST_CASE("contact lost carries zero force and no solution") {
    core::BiteResult result;
    result.status = core::BiteStatus::contact_lost;
    const json body = api::bite_result_json(result);
    CHECK(body["status"] == "contact_lost");
    CHECK(body["force_kN"] == 0.0);
    CHECK(body["neutral_point_mm"].is_null());
    CHECK(body["contact_length_mm"].is_null());
}

TEST_CASE("non-finite values of a failed solve are written as null") {
    core::BiteResult result;
    result.status = core::BiteStatus::solver_failure;
    result.force = std::nan("");
    const json body = api::bite_result_json(result);
    CHECK(body["status"] == "solver_failure");
    CHECK(body["force_kN"].is_null());
    CHECK(body.dump().find("NaN") == std::string::npos);
}
