#include "fuzz/scenario_from_bytes.h"

#include <cmath>
#include <string>

#include "api/field_errors.h"
#include "api/scenario_consistency.h"
#include "api/scenario_schema.h"
#include "api/units.h"

namespace rollgap::fuzz {

namespace {

// The value of a numeric field in the client's unit, inside `range`.
double pick_number(FuzzInput& input, std::uint8_t selector, const api::Interval& range) {
    const double inner_min = range.min_open ? std::nextafter(range.min, range.max) : range.min;
    const double inner_max = range.max_open ? std::nextafter(range.max, range.min) : range.max;
    double value = inner_min;
    if (selector % 4 == 1) {
        value = inner_max;
    } else if (selector % 4 >= 2) {
        value = input.between(inner_min, inner_max);
    }
    // The log map can round a hair outside; the table's own test is the arbiter.
    if (!range.contains(value)) value = inner_min;
    return value;
}

}  // namespace

std::optional<core::Scenario> scenario_from_bytes(FuzzInput& input) {
    core::Scenario scenario;
    for (const api::ScenarioField& field : api::scenario_fields()) {
        const std::uint8_t selector = input.byte();
        if (selector < 128) continue;  // the default
        switch (field.kind) {
            case api::FieldKind::number:
                field.number(scenario) =
                    api::to_si(pick_number(input, selector, field.range), field.unit);
                break;
            case api::FieldKind::integer: {
                int value =
                    static_cast<int>(std::lround(pick_number(input, selector, field.range)));
                if (field.even && value % 2 != 0) value += value < field.range.max ? 1 : -1;
                field.integer(scenario) = value;
                break;
            }
            case api::FieldKind::boolean: field.flag(scenario) = (selector & 1) != 0; break;
            case api::FieldKind::choice:
                field.write_choice(scenario, field.choices[selector % field.choices.size()]);
                break;
        }
    }
    api::FieldErrors errors;
    api::check_scenario_consistency(scenario, "", errors);
    if (!errors.empty()) return std::nullopt;
    return scenario;
}

}  // namespace rollgap::fuzz
