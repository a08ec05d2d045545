#pragma once
// The critical speed of a stand as a figure of its lubricant viscosity and asperity factor
// (x = (eta0 Pa s, m_a)): what the propagation tests carry a posterior to (core/propagation.h).
#include <optional>

#include <Eigen/Dense>

#include "core/propagation.h"
#include "core/scenario.h"
#include "core/stability.h"

namespace rollgap::test {

inline core::Figure critical_speed_of_viscosity_and_asperity(const core::Scenario& base) {
    return [base](const Eigen::VectorXd& x) -> std::optional<double> {
        core::Scenario s = base;
        s.lubricant.viscosity = x(0);
        s.friction.asperity_factor = x(1);
        core::CriticalSpeedOptions search;
        search.stop_at_crossing = true;
        const core::CriticalSpeedResult r = core::critical_speed(s, search);
        if (r.status != core::CriticalSpeedStatus::found) return std::nullopt;
        return r.critical_speed;
    };
}

}  // namespace rollgap::test
