#include "api/result_json.h"

#include <string>

#include "api/quantity_json.h"
#include "api/result_table.h"

namespace rollgap::api {
namespace {

using core::BitePoint;
using core::BiteResult;
using core::BiteStatus;
using Points = std::vector<BitePoint>;

nlohmann::json column(const Points& points, double BitePoint::*member, Unit unit) {
    nlohmann::json values = nlohmann::json::array();
    for (const BitePoint& point : points) values.push_back(quantity_json(point.*member, unit));
    return values;
}

// A distribution column: its name, description, member of BitePoint and unit.
Member<Points> column_member(std::string_view name, std::string_view description,
                             double BitePoint::*member, Unit unit) {
    return {name, description, array_schema(number_schema(unit)),
            [member, unit](const Points& points) { return column(points, member, unit); }};
}

bool solved(const BiteResult& result) { return result.status == BiteStatus::ok; }

// Core leaves the quantities of an unsolved bite at 0; 0 would read as a result.
Member<BiteResult> solution_member(std::string_view name, std::string_view description,
                                   double BiteResult::*member, Unit unit) {
    return {name, description, number_schema(unit), [member, unit](const BiteResult& result) {
                return solved(result) ? quantity_json(result.*member, unit)
                                      : nlohmann::json(nullptr);
            }};
}

// Force and torque are also known (0) when the strip is not reduced.
Member<BiteResult> load_member(std::string_view name, std::string_view description,
                               double BiteResult::*member, Unit unit) {
    return {name, description, number_schema(unit), [member, unit](const BiteResult& result) {
                return solved(result) || result.status == BiteStatus::contact_lost
                           ? quantity_json(result.*member, unit)
                           : nlohmann::json(nullptr);
            }};
}

// The bite geometry is known when the bite skids too.
Member<BiteResult> geometry_member(std::string_view name, std::string_view description,
                                   double BiteResult::*member, Unit unit) {
    return {name, description, number_schema(unit), [member, unit](const BiteResult& result) {
                return solved(result) || result.status == BiteStatus::skidding
                           ? quantity_json(result.*member, unit)
                           : nlohmann::json(nullptr);
            }};
}

}  // namespace

const ResultTable<Points>& bite_distribution_table() {
    static const ResultTable<Points> table{
        "BiteDistribution",
        "Quantities along the bite, columnar: one array per quantity, all of the same length (the bite's "
        "integration points, numerics.bite_intervals + 1, from the entry to the exit). Present when "
        "options.distributions is true and the bite solved. Non-finite values are null.",
        {
            column_member("x_mm", "Distance from the exit.", &BitePoint::x, units::millimetre),
            column_member("pressure_MPa", "Normal pressure.", &BitePoint::pressure,
                          units::megapascal),
            column_member("friction_MPa", "Friction (shear) stress, signed.", &BitePoint::friction,
                          units::megapascal),
            column_member("film_um", "Lubricant film thickness.", &BitePoint::film,
                          units::micrometre),
            column_member("film_ratio", "Film thickness over the combined roughness.",
                          &BitePoint::film_ratio, units::one),
            column_member("contact_ratio", "Fraction of the load carried by asperities, [0, 1].",
                          &BitePoint::contact_ratio, units::one),
            column_member("strip_speed_m_per_s", "Strip speed.", &BitePoint::strip_speed,
                          units::metre_per_second),
            column_member("thickness_mm", "Strip thickness.", &BitePoint::thickness,
                          units::millimetre),
            {"regime", "Lubrication regime at each point.",
             array_schema(enum_schema({"boundary", "mixed", "full_film"})),
             [](const Points& points) {
                 nlohmann::json regimes = nlohmann::json::array();
                 for (const BitePoint& point : points)
                     regimes.push_back(core::to_string(point.regime));
                 return regimes;
             }},
        }};
    return table;
}

const ResultTable<BiteResult>& skidding_table() {
    static const ResultTable<BiteResult> table{
        "Skidding",
        "Why the bite skids. Present when status is skidding.",
        {
            {"neutral_point_left_at", "The end of the bite the neutral point left through.",
             enum_schema({"entry", "exit"}),
             [](const BiteResult& result) {
                 return nlohmann::json(result.skid_at_exit ? "exit" : "entry");
             }},
            {"residual_MPa",
             "Pressure mismatch at the end nearest a root: how far the bite is from driving the strip.",
             number_schema(units::megapascal),
             [](const BiteResult& result) {
                 return quantity_json(result.skid_residual, units::megapascal);
             }},
        }};
    return table;
}

const ResultTable<BiteResult>& bite_result_table() {
    static const ResultTable<BiteResult> table{
        "RollGapResult",
        "The steady roll bite. A quantity the solve did not produce is null: with `skidding` everything but "
        "the bite geometry, with `contact_lost` everything but force and torque (0), with `solver_failure` "
        "everything.",
        {
            {"status",
             "`ok`: a steady bite. `skidding`: the rolls cannot drive the strip (no neutral point in the bite). "
             "`contact_lost`: the strip is not reduced. `solver_failure`: the solver did not converge.",
             enum_schema({"ok", "skidding", "contact_lost", "solver_failure"}),
             [](const BiteResult& result) {
                 return nlohmann::json(core::to_string(result.status));
             }},
            {"message", "Why the status is not ok, for humans.", string_schema(),
             [](const BiteResult& result) {
                 return result.message != nullptr && result.message[0] != '\0'
                            ? nlohmann::json(result.message)
                            : absent();
             },
             true},
            load_member("force_kN", "Roll force.", &BiteResult::force, units::kilonewton),
            load_member("torque_kN_m", "Roll torque (both rolls).", &BiteResult::torque,
                        units::kilonewton_metre),
            solution_member("neutral_point_mm",
                            "Neutral point, distance from the exit, in [0, contact_length_mm].",
                            &BiteResult::neutral_point, units::millimetre),
            solution_member("entry_speed_m_per_s", "Strip speed at the entry.",
                            &BiteResult::entry_speed, units::metre_per_second),
            solution_member("exit_speed_m_per_s", "Strip speed at the exit.",
                            &BiteResult::exit_speed, units::metre_per_second),
            solution_member("forward_slip",
                            "Forward slip, exit strip speed over roll speed minus 1.",
                            &BiteResult::forward_slip, units::one),
            solution_member("inlet_film_um", "Lubricant film thickness at the bite inlet.",
                            &BiteResult::inlet_film, units::micrometre),
            geometry_member(
                "roll_radius_mm",
                "Work-roll radius in the bite: the flattened radius with rolls.flattening, else the "
                "nominal radius.",
                &BiteResult::roll_radius, units::millimetre),
            geometry_member("contact_length_mm", "Projected contact length of the bite.",
                            &BiteResult::contact_length, units::millimetre),
            geometry_member("inlet_angle_rad", "Bite angle at the entry.", &BiteResult::inlet_angle,
                            units::radian),
            solution_member("mean_friction_coefficient",
                            "Torque-equivalent mean friction coefficient.",
                            &BiteResult::mean_friction_coefficient, units::one),
            {"skidding", "Present when status is skidding.", ref_schema("Skidding"),
             [](const BiteResult& result) {
                 return result.status == BiteStatus::skidding ? skidding_table().write(result)
                                                              : absent();
             },
             true},
            {"distribution", "Present when options.distributions is true and the bite solved.",
             ref_schema("BiteDistribution"),
             [](const BiteResult& result) {
                 return result.distribution.empty()
                            ? absent()
                            : bite_distribution_table().write(result.distribution);
             },
             true},
        }};
    return table;
}

std::vector<ResultSchema> bite_result_schemas() {
    return {result_schema(bite_distribution_table()), result_schema(skidding_table()),
            result_schema(bite_result_table())};
}

nlohmann::json bite_result_json(const core::BiteResult& result) {
    return bite_result_table().write(result);
}

}  // namespace rollgap::api
