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

// The facade as an Evaluator. The synchronous HTTP path recognises it (is_facade) and computes
// the request it prepared on the connection thread with service::run instead of preparing it
// again; an injected evaluator is handed the request's JSON after the same preparation.
struct FacadeEvaluator {
    Outcome operator()(const nlohmann::json& request, const core::Control& control) const {
        return evaluate(request, control);
    }
};
inline Evaluator facade_evaluator() { return FacadeEvaluator{}; }
inline bool is_facade(const Evaluator& evaluator) {
    return evaluator.target<FacadeEvaluator>() != nullptr;
}

}  // namespace rollgap::service
