#pragma once
// What computes an outcome for the HTTP layer. The default is the facade (service::evaluate);
// tests inject slow or blocking ones.

#include <functional>

#include <nlohmann/json.hpp>

#include "core/control.h"
#include "service/evaluate.h"

namespace rollgap::service {

using Evaluator =
    std::function<Outcome(const nlohmann::json& request, const core::Control& control)>;
Evaluator facade_evaluator();

}  // namespace rollgap::service
