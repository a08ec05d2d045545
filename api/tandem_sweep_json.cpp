#include "api/tandem_sweep_json.h"

#include <array>
#include <string_view>

#include "api/chatter_json.h"
#include "api/options_reader.h"
#include "api/sweep_json.h"
#include "api/tandem_json.h"
#include "core/sweep.h"

namespace rollgap::api {
// Named, not anonymous: the unity build puts this file beside the stand's sweep and the tandem
// answer, whose anonymous helpers have the same names.
namespace tandem_sweep_detail {

using nlohmann::json;
using namespace units;

constexpr std::array<std::string_view, 5> sweep_members{"parameter", "values", "range", "quantity",
                                                        "critical_speed"};

struct SweepOutput {
    const TandemSweepPlan* plan = nullptr;
    json points;
    json chatter_type_changes;
};

const ResultTable<SweepOutput>& result_table() {
    static const ResultTable<SweepOutput> table{
        "TandemSweepResult",
        "A mill sweep: one value of the tandem document over the values, the mill at each.",
        {
            {"parameter", "The swept pointer into the tandem document.", string_schema(),
             [](const SweepOutput& o) { return json(o.plan->parameter); }},
            {"unit", "The swept value's unit (UCUM).", string_schema(),
             [](const SweepOutput& o) { return json(o.plan->unit.code); }},
            {"value_name", "The member under which each point carries its value.", string_schema(),
             [](const SweepOutput& o) { return json(sweep_value_name(o.plan->unit)); }},
            {"quantity", "What each point holds.", enum_schema({"critical_speed", "stability"}),
             [](const SweepOutput& o) { return json(to_string(o.plan->spec.quantity)); }},
            {"points", "One per value, in the order of options.values or the range.",
             array_schema({{"oneOf", json::array({ref_schema("TandemSweepCriticalSpeedPoint"),
                                                  ref_schema("TandemSweepStabilityPoint")})}}),
             [](const SweepOutput& o) { return o.points; }},
            {"chatter_type_changes",
             "Each pair of consecutive values whose points differ in chatter type by shape (the "
             "headline crossing's, or the rightmost root's).",
             chatter_type_changes_schema({{"type", "number"}}),
             [](const SweepOutput& o) { return o.chatter_type_changes; }},
        }};
    return table;
}

}  // namespace tandem_sweep_detail

TandemSweepPlan tandem_sweep_plan_from_json(const nlohmann::json& options,
                                            const std::string& pointer,
                                            const core::Mill* valid_mill, FieldErrors& errors) {
    TandemSweepPlan plan;
    const OptionsReader reader(options, pointer, tandem_sweep_detail::sweep_members, errors);
    if (!reader.is_object()) return plan;
    const nlohmann::json document =
        valid_mill != nullptr ? resolved_tandem_json(*valid_mill) : nlohmann::json();
    const auto parameter =
        read_tandem_parameter(reader, valid_mill != nullptr ? &document : nullptr, plan.unit);
    nlohmann::json echo_spec = nlohmann::json::object();
    read_tandem_point_spec(reader, plan.spec, echo_spec);
    nlohmann::json echo_values;
    const auto points = read_sweep_points(reader, echo_values, max_tandem_sweep_points);
    if (parameter && *parameter == "/speed_m_per_s" &&
        plan.spec.quantity == TandemSweepQuantity::critical_speed) {
        // Every point would be the same search: the speed is what it scans.
        errors.add({reader.at("parameter"),
                    "the critical-speed search scans the mill speed itself: sweep another "
                    "number, or the mill speed with quantity \"stability\"",
                    std::nullopt, std::nullopt});
    } else if (parameter) {
        plan.parameter = *parameter;
    }
    if (!plan.parameter.empty() && points && valid_mill != nullptr) {
        TandemValues built = tandem_values(*points, document, plan.parameter, errors);
        plan.values = std::move(built.values);
        plan.mills = std::move(built.mills);
    }

    plan.resolved_options = {
        {"parameter", parameter ? nlohmann::json(*parameter) : nlohmann::json(nullptr)},
        {"quantity", echo_spec["quantity"]},
    };
    if (echo_values.is_object()) plan.resolved_options.update(echo_values);
    if (echo_spec.contains("critical_speed"))
        plan.resolved_options["critical_speed"] = std::move(echo_spec["critical_speed"]);
    return plan;
}

nlohmann::json tandem_sweep_points_json(const TandemSweepPlan& plan, std::size_t first,
                                        std::size_t count, const core::Control& control) {
    const std::string key = sweep_value_name(plan.unit);
    nlohmann::json points = nlohmann::json::array();
    for (std::size_t i = first; i < first + count && i < plan.mills.size(); ++i) {
        if (control.should_stop()) break;  // the caller reports the cancellation
        nlohmann::json point = tandem_point_json(plan.mills[i], plan.spec, control);
        point[key] = plan.values[i];
        points.push_back(std::move(point));
        control.report(static_cast<double>(i + 1 - first) / static_cast<double>(count));
    }
    return points;
}

nlohmann::json tandem_sweep_result_json(const TandemSweepPlan& plan, nlohmann::json points) {
    // From the documents of all points: a point's neighbour may have been computed in another
    // chunk.
    nlohmann::json changes = chatter_type_changes_json(
        points, core::sequence_neighbours(static_cast<int>(points.size())),
        [&plan](int i) { return nlohmann::json(plan.values[static_cast<std::size_t>(i)]); });
    return tandem_sweep_detail::result_table().write(
        {&plan, std::move(points), std::move(changes)});
}

std::vector<ResultSchema> tandem_sweep_result_schemas() {
    std::vector<ResultSchema> schemas;
    for (const TandemSweepQuantity q :
         {TandemSweepQuantity::critical_speed, TandemSweepQuantity::stability})
        schemas.push_back({tandem_point_component(q), sweep_point_schema(tandem_point_schema(q))});
    schemas.push_back(result_schema(tandem_sweep_detail::result_table()));
    return schemas;
}

std::span<const CsvTable> tandem_sweep_csv_tables() {
    static const std::vector<CsvTable> tables{
        {"points",
         "One row per swept value, the value first.",
         "",
         {},
         "/points",
         [](const nlohmann::json& result) {
             return with_tandem_point_columns({result.value("value_name", std::string("value"))},
                                              result);
         }}};
    return tables;
}

}  // namespace rollgap::api
