#pragma once
// Mills shared by the verification report (tools/verify_mill) and the mill tests
// (tests/core/test_mill_*.cpp): the single stand as a mill of one stand, the default mill's last
// two stands with one span of a given length, and the delays replaced by cascades of first-order
// Padé sections.

#include <Eigen/Dense>

#include "core/mill/mill.h"
#include "core/mill/mill_model.h"
#include "core/scenario.h"

namespace rollgap::tools::mills {

// The single-stand defaults as a mill of one stand: entry span 5 m at 18 MPa, the exit at the
// single stand's constant front tension (0).
inline core::Mill one_stand_mill(const core::Scenario& s = core::Scenario{}) {
    core::Mill m;
    m.stands = {s};
    m.thickness = {s.strip.entry_thickness, core::exit_thickness(s)};
    m.width = s.strip.width;
    m.youngs_modulus = s.strip.youngs_modulus;
    m.entry = core::MillBoundary::span;
    m.entry_span_length = s.tensions.back.span_length;
    m.entry_tension = s.tensions.back.stress;
    m.exit = core::MillBoundary::constant;
    m.exit_tension = s.tensions.front.stress;
    m.speed = s.rolls.speed;
    return m;
}

// The default mill's last two stands (1.60 -> 1.36 -> 1.20 mm) with an interstand span of
// `span` m, the entry tension the default's third interstand set point.
inline core::Mill two_stand_mill(double span) {
    const core::Mill d = core::default_mill();
    core::Mill m = d;
    m.stands = {d.stands[3], d.stands[4]};
    m.thickness = {d.thickness[3], d.thickness[4], d.thickness[5]};
    m.span_length = {span};
    m.interstand_tension = {d.interstand_tension[3]};
    m.entry_tension = d.interstand_tension[2];
    return m;
}

// The mill with each delay e^{-s tau} replaced by k sections (1 - s h / 2) / (1 + s h / 2),
// h = tau / k: x' = (2/h)(in - x), out = 2x - in. The delayed rate u' is the same cascade on
// y' = C A0 z (C B = C B' = 0: the exit thickness has no direct input), so the closed loop is
// sZ = A0 Z + (B + s B') P(s) C Z exactly, plus the cascades' own poles at -2/h.
inline Eigen::MatrixXd pade_closed_loop(const core::MillLinearisation& lin, int k) {
    const Eigen::Index n = lin.jacobian.rows(), p = lin.input.cols();
    const Eigen::Index size = n + 2 * k * p;
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(size, size);
    a.topLeftCorner(n, n) = lin.jacobian;
    for (Eigen::Index i = 0; i < p; ++i) {
        const double h = lin.delay[static_cast<std::size_t>(i)] / k;
        for (int chain = 0; chain < 2; ++chain) {
            // the signal entering the cascade as a row over the whole state
            Eigen::RowVectorXd in = Eigen::RowVectorXd::Zero(size);
            in.head(n) = chain == 0 ? Eigen::RowVectorXd(lin.output.row(i))
                                    : Eigen::RowVectorXd(lin.output.row(i) * lin.jacobian);
            for (int j = 0; j < k; ++j) {
                const Eigen::Index x = n + (2 * i + chain) * k + j;
                a.row(x) += (2.0 / h) * in;
                a(x, x) -= 2.0 / h;
                Eigen::RowVectorXd out = -in;
                out(x) += 2.0;
                in = out;
            }
            const Eigen::VectorXd column = chain == 0 ? lin.input.col(i) : lin.input_rate.col(i);
            a.topRows(n) += column * in;
        }
    }
    return a;
}

}  // namespace rollgap::tools::mills
