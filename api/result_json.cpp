#include "api/result_json.h"

#include <cmath>
#include <functional>
#include <string>

#include "api/units.h"

namespace rollgap::api {
namespace {

nlohmann::json quantity(double si_value, Unit unit) {
    if (!std::isfinite(si_value)) return nullptr;
    return from_si(si_value, unit);
}

nlohmann::json column(const std::vector<core::BitePoint>& points, double core::BitePoint::*member, Unit unit) {
    nlohmann::json values = nlohmann::json::array();
    for (const core::BitePoint& point : points) values.push_back(quantity(point.*member, unit));
    return values;
}

nlohmann::json distribution_json(const std::vector<core::BitePoint>& points) {
    nlohmann::json regimes = nlohmann::json::array();
    for (const core::BitePoint& point : points) regimes.push_back(core::to_string(point.regime));
    return {
        {"x_mm", column(points, &core::BitePoint::x, units::millimetre)},
        {"pressure_MPa", column(points, &core::BitePoint::pressure, units::megapascal)},
        {"friction_MPa", column(points, &core::BitePoint::friction, units::megapascal)},
        {"film_um", column(points, &core::BitePoint::film, units::micrometre)},
        {"film_ratio", column(points, &core::BitePoint::film_ratio, units::one)},
        {"contact_ratio", column(points, &core::BitePoint::contact_ratio, units::one)},
        {"strip_speed_m_per_s", column(points, &core::BitePoint::strip_speed, units::metre_per_second)},
        {"thickness_mm", column(points, &core::BitePoint::thickness, units::millimetre)},
        {"regime", std::move(regimes)},
    };
}

}  // namespace

nlohmann::json bite_result_json(const core::BiteResult& result) {
    const bool solved = result.status == core::BiteStatus::ok;
    const bool no_contact = result.status == core::BiteStatus::contact_lost;
    const bool geometry_known = solved || result.status == core::BiteStatus::skidding;
    // Core leaves the quantities of an unsolved bite at 0; 0 would read as a result.
    const auto solution = [solved](double si_value, Unit unit) {
        return solved ? quantity(si_value, unit) : nlohmann::json(nullptr);
    };
    const auto load = [solved, no_contact](double si_value, Unit unit) {
        return solved || no_contact ? quantity(si_value, unit) : nlohmann::json(nullptr);
    };
    nlohmann::json body = {
        {"status", core::to_string(result.status)},
        {"force_kN", load(result.force, units::kilonewton)},
        {"torque_kN_m", load(result.torque, units::kilonewton_metre)},
        {"neutral_point_mm", solution(result.neutral_point, units::millimetre)},
        {"entry_speed_m_per_s", solution(result.entry_speed, units::metre_per_second)},
        {"exit_speed_m_per_s", solution(result.exit_speed, units::metre_per_second)},
        {"forward_slip", solution(result.forward_slip, units::one)},
        {"inlet_film_um", solution(result.inlet_film, units::micrometre)},
        {"roll_radius_mm", geometry_known ? quantity(result.roll_radius, units::millimetre) : nullptr},
        {"contact_length_mm", geometry_known ? quantity(result.contact_length, units::millimetre) : nullptr},
        {"inlet_angle_rad", geometry_known ? quantity(result.inlet_angle, units::radian) : nullptr},
        {"mean_friction_coefficient", solution(result.mean_friction_coefficient, units::one)},
    };
    if (result.message != nullptr && result.message[0] != '\0') body["message"] = result.message;
    if (result.status == core::BiteStatus::skidding) {
        body["skidding"] = {
            // The end of the bite the neutral point left through.
            {"neutral_point_left_at", result.skid_at_exit ? "exit" : "entry"},
            // Pressure mismatch at the end nearest a root: how far from driving the strip.
            {"residual_MPa", quantity(result.skid_residual, units::megapascal)},
        };
    }
    if (!result.distribution.empty()) body["distribution"] = distribution_json(result.distribution);
    return body;
}

}  // namespace rollgap::api
