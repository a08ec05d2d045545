#include "core/mill/mill_stability.h"

#include "core/mill/mill_model.h"

namespace rollgap::core {

MillStability mill_frozen_stability(const Mill& mill) {
    MillStability out;
    out.steady = mill_steady_state(mill);
    out.frozen.speed = mill.speed;
    if (out.steady.status != MillSteadyStatus::ok) {
        out.frozen.steady_status =
            out.steady.stand >= 0
                ? out.steady.stands[static_cast<std::size_t>(out.steady.stand)].status
                : BiteStatus::solver_failure;
        if (out.frozen.steady_status == BiteStatus::ok)
            out.frozen.steady_status = BiteStatus::solver_failure;
        return out;
    }
    const MillModel model(mill, out.steady);
    if (model.status() != BiteStatus::ok) {
        out.frozen.steady_status = model.status();
        return out;
    }
    out.frozen = linear_stability(model);
    out.frozen.speed = mill.speed;
    out.frozen.steady_status = BiteStatus::ok;
    out.frozen.force = out.steady.stands.back().force;  // the last stand's
    return out;
}

MillSpeedStability mill_stability_at(const Mill& mill, const RegenerativeOptions& options) {
    MillSpeedStability out;
    const MillStability frozen = mill_frozen_stability(mill);
    out.steady = frozen.steady;
    out.frozen = frozen.frozen;
    if (out.frozen.status != DynamicsStatus::ok) return out;
    const MillModel model(mill, out.steady);
    const MillLinearisation lin = model.linearise(model.equilibrium());
    if (lin.status != DynamicsStatus::ok) return out;
    out.delay = lin.delay;
    const TransportTransfer transfer = transport_transfer(lin);
    out.margin = regenerative_margin(transfer, options);
    out.nominal = nominal_delay_root_count(transfer, 0.0);
    if (out.nominal.ok) out.rightmost = rightmost_delay_root(transfer, out.nominal);
    out.nominal_stable = out.nominal.ok && out.nominal.count == 0;
    out.delay_independent_stable =
        out.margin.ok && out.margin.frozen_stable && out.margin.margin < 1.0;
    return out;
}

CriticalSpeedResult mill_frozen_critical_speed(const Mill& mill,
                                               const CriticalSpeedOptions& options,
                                               const Control& control) {
    const auto at = [&mill](double speed, bool) {
        Mill m = mill;
        m.speed = speed;
        return mill_frozen_stability(m).frozen;
    };
    return critical_speed_search(at, options, control);
}

}  // namespace rollgap::core
