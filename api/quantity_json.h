#pragma once
// SI value → JSON number in an engineering unit; non-finite values (a quantity that does not
// exist for this outcome) are null, never NaN (JSON has none).

#include <cmath>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/units.h"

namespace rollgap::api {

inline nlohmann::json quantity_json(double value_si, Unit unit) {
    if (!std::isfinite(value_si)) return nullptr;
    return from_si(value_si, unit);
}

inline nlohmann::json quantities_json(const std::vector<double>& values_si, Unit unit) {
    nlohmann::json values = nlohmann::json::array();
    for (const double value : values_si) values.push_back(quantity_json(value, unit));
    return values;
}

}  // namespace rollgap::api
