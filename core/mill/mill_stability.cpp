#include "core/mill/mill_stability.h"

#include <cmath>
#include <numbers>

#include "core/mill/mill_model.h"
#include "core/stand_structure.h"

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

std::vector<MarginFactors> margin_factors(const Mill& mill, const MillModel& model,
                                          const TransportTransfer& transfer,
                                          const RegenerativeMargin& margin) {
    std::vector<MarginFactors> out;
    const Eigen::Index p = transfer.spans();
    if (!margin.ok || p == 0 || margin.transfer.rows() != p || model.status() != BiteStatus::ok)
        return out;
    const Eigen::VectorXd z = model.equilibrium();
    const double omega = 2.0 * std::numbers::pi * margin.frequency_Hz;
    // the worst input: u = D^-1 v, v the top right singular vector of D M D^-1
    const Eigen::VectorXcd u = margin_worst_input(margin);
    const double total = u.squaredNorm();
    for (Eigen::Index i = 0; i < p; ++i) {
        MarginFactors f;
        f.span = static_cast<int>(i);
        f.worst_input_share = total > 0.0 ? std::norm(u(i)) / total : 0.0;
        f.tension_loop_gain = std::abs(margin.transfer(i, i));
        if (i + 1 < p) f.thickness_gain = std::abs(margin.transfer(i + 1, i));
        const int receiving = static_cast<int>(i) + 1;
        const StandBlock& block = model.stand(receiving);
        const double y1 = mill.thickness[static_cast<std::size_t>(receiving)];
        const double h = 1e-6 * y1;
        const BiteResult plus = block.solve_bite(model.bite_state(receiving, z.data(), h));
        const BiteResult minus = block.solve_bite(model.bite_state(receiving, z.data(), -h));
        if (plus.status == BiteStatus::ok && minus.status == BiteStatus::ok) {
            f.force_per_entry_thickness = (plus.force - minus.force) / (2.0 * h);
            f.entry_speed_per_entry_thickness = (plus.entry_speed - minus.entry_speed) / (2.0 * h);
        } else {
            f.force_per_entry_thickness = f.entry_speed_per_entry_thickness = std::nan("");
        }
        const StructureMatrices m = structure_matrices(block.scenario().structure);
        const Vector6 g = gap_direction();
        const Eigen::Matrix<std::complex<double>, 6, 6> dynamic =
            m.structural_stiffness.cast<std::complex<double>>() -
            omega * omega * m.mass.cast<std::complex<double>>() +
            std::complex<double>(0.0, omega) * m.damping.cast<std::complex<double>>();
        const Eigen::Matrix<std::complex<double>, 6, 1> response =
            dynamic.partialPivLu().solve(g.cast<std::complex<double>>());
        f.compliance = std::abs(g.cast<std::complex<double>>().dot(response));
        out.push_back(f);
    }
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
    out.factors = margin_factors(mill, model, transfer, out.margin);
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
