#pragma once
// The mill's dynamics with the thickness transport frozen (docs/model.md §12.4): each stand a
// stand block (core/stand_block.h, 13 states) on its steady state, the spans' strip forces per
// width T (N/m) as states, y1 of every stand held at its steady value. Its eigenvalues are the
// mill's frozen stability (tension coupling only); its Jacobian A0 is the frozen part of the
// regenerative analysis. State: the stands' blocks in order, then the spans: the entry span (if
// a span), the N - 1 interstand spans, the exit span (if a span).
//   stand i sees s_b = T_back / y1_i and s_f = T_front / y2_i(t) (a boundary held at a constant
//   stress gives that stress);
//   T_i' = (E ybar_i / L_i) ((u1_{i+1} - u1_{i+1,ref}) - (u2_i - u2_i,ref)) between stands,
//   T_0' = (E y1_1 / L_0)(u1_1 - u1_1,ref), T_N' = (E y2_N / L_N)(u2_N,ref - u2_N).
// Under the `segments` span model (§12.1) a span of n segments has n forces T_1..T_n (T_1 at the
// stand behind it, T_n at the stand ahead: the forces the stands see) and the n - 1 node speeds
// v_1..v_{n-1} (deviations from the steady strip speed), in that order:
//   T_k' = (E ybar n / L)(v_k - v_{k-1}), v_0 = u2 - u2_ref behind, v_n = u1 - u1_ref ahead;
//   (rho ybar L / n) v_k' = T_{k+1} - T_k.
// One segment is the spring law exactly.

#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "core/dynamic_model.h"
#include "core/mill/mill.h"
#include "core/stand_block.h"

namespace rollgap::core {

// The mill linearised about its steady state with the thickness transport as inputs
// (docs/model.md §12.5): z' = A0 z + sum_i (B_i u_i + B'_i u_i'), u_i = delta y1_{i+1}, the
// thickness entering stand i+1 (i = 0..N-2), fed back as u_i(t) = y_i(t - tau_i) with
// y_i = C_i z = delta y2_i, stand i's exit thickness.
struct MillLinearisation {
    DynamicsStatus status = DynamicsStatus::solver_failure;
    Eigen::MatrixXd jacobian;    // A0, n x n
    Eigen::MatrixXd input;       // B, n x p: df/d(y1 of stand i+1)
    Eigen::MatrixXd input_rate;  // B', n x p: df/d(y1' of stand i+1), the inlet film's theta'
    Eigen::MatrixXd output;      // C, p x n: delta y2 of stand i
    std::vector<double> delay;   // tau_i = L_i / u2_i,ref, s
    // N x n: d u2_i / dz, each stand's exit strip speed (the strip positions' rates of the time
    // domain, core/mill/mill_time.h)
    Eigen::MatrixXd exit_speed;
};

// Where a right-hand side of the mill found no state: the stand whose bite failed or lost
// contact, or the span gone slack, numbered by the stand behind it (0: the entry span, N: the
// exit span; span i + 1 joins stands i and i + 1).
struct MillFailure {
    int stand = -1;
    int span = -1;
};

class MillModel final : public DynamicModel {
public:
    // `steady` must be ok (mill_steady_state of `mill`); each stand's dynamics run on its
    // dynamics scenario at its solved roll speed (the reference bites re-solved with
    // numerics.dynamics_bite_intervals: the speeds the spans compare with are those bites').
    MillModel(const Mill& mill, const MillSteadyState& steady);

    int size() const override { return size_; }
    Eigen::VectorXd equilibrium() const override;
    DynamicsStatus rhs(double t, const double* z, double* zdot) const override;
    Linearisation jacobian(const Eigen::VectorXd& z, double t) const override;
    double perturbation(int index, const Eigen::VectorXd& z) const override;
    double absolute_tolerance(int index) const override;
    int margin_count() const override;
    void limit_margins(double t, const double* z, double* margins) const override;
    DynamicsStatus margin_status(int index) const override;
    int stand_count() const override { return static_cast<int>(stands_.size()); }
    int displacement_index(int stand) const override {
        return stands_[static_cast<std::size_t>(stand)].offset();
    }

    // The reference states the stand blocks were built on: ok for every stand unless `status`
    // says otherwise (a stand whose dynamics bite does not solve).
    BiteStatus status() const { return status_; }
    int failed_stand() const { return failed_stand_; }

    // The state index of the span force stand i sees behind (back) and ahead of it (front), -1
    // for a constant boundary (under `segments`: the end segment's force at that stand).
    int back_span(int stand) const;
    int front_span(int stand) const;

    // The states of one span: `count` consecutive indices from `first` (the segments' forces,
    // then the node speeds; one force under `spring`). Numbered as MillFailure: 0 the entry
    // span, i + 1 the span between stands i and i + 1, N the exit span; count 0 if that span is
    // a constant boundary.
    struct SpanStates {
        int first = -1;
        int count = 0;
        int segments = 0;
    };
    SpanStates span_states(int span) const;

    // The bite inputs of stand i at state z, its entering thickness moved by `entry_deviation`
    // from the steady one (the transport; zero when frozen).
    BiteState bite_state(int stand, const double* z, double entry_deviation = 0.0) const;

    // z' with the thickness transport as inputs: stand i enters at y1_i + entry_deviation[i]
    // with rate entry_rate[i] (N values each; stand 0's are the mill's entry, zero here).
    DynamicsStatus rhs_with_transport(double t, const double* z, const double* entry_deviation,
                                      const double* entry_rate, double* zdot) const;

    // The time domain's right-hand side (docs/model.md §12.9, core/mill/mill_time.h): as
    // rhs_with_transport, but stand i's entry rate is entry_rate_per_speed[i] times stand i-1's
    // exit speed u2_{i-1}(t) at this state (the transport's dt_d/dt = u2(t) / u2(t_d) needs the
    // upstream bite of the same evaluation); every stand's u2_i(t) goes to exit_speed (N values),
    // and a failure says where in `failure` (optional).
    DynamicsStatus rhs_with_history(double t, const double* z, const double* entry_deviation,
                                    const double* entry_rate_per_speed, double* zdot,
                                    double* exit_speed, MillFailure* failure = nullptr) const;

    // A0, B, B', C, the exit speeds' rows and the delays at z (the steady state z0 for the
    // stability analyses); without `transport`, A0 and the exit speeds' rows alone.
    MillLinearisation linearise(const Eigen::VectorXd& z, bool transport = true) const;

    // Stand i's block (its scenario, reference bite and bite memo) and span i's length (the
    // interstand span after stand i), m.
    const StandBlock& stand(int i) const { return stands_[static_cast<std::size_t>(i)]; }
    double span_length(int i) const { return span_length_[static_cast<std::size_t>(i)]; }

    // J_b of stand i scaled by gains[i] in the linearisations (jacobian(), linearise()): the
    // bite-gain sensitivity of a root, J_b,i -> (1 + kappa_i) J_b,i (docs/model.md §12.7).
    // Empty: every gain 1. The rates (rhs) are not affected.
    void set_bite_gains(std::vector<double> gains) { bite_gain_ = std::move(gains); }

private:
    // The assembly of jacobian() and linearise(): A0 into out.jacobian, and with `transport`
    // B and B' (the entering thickness of stands 2..N as extra input columns).
    void assemble(const Eigen::VectorXd& z, bool transport, MillLinearisation& out) const;
    // rhs_with_transport and rhs_with_history: `rate_per_speed` says which the rates are.
    DynamicsStatus evaluate_rates(const double* z, const double* entry_deviation,
                                  const double* entry_rate, bool rate_per_speed, double* zdot,
                                  double* exit_speed, MillFailure* failure) const;

    struct Span {
        int index = -1;          // T_1's state; T_k at index + k - 1, v_k at index + n + k - 1
        int segments = 1;        // n
        double thickness = 0.0;  // ybar, m
        double stiffness = 0.0;  // of one segment, E ybar n / L, (N/m)/m
        double mass = 0.0;       // of one node, rho ybar L / n, kg/m^2 (per width)
        int upstream = -1;       // the stand delivering into it, -1: the entry bridle
        int downstream = -1;     // the stand taking from it, -1: the exit coiler
        int first_speed() const { return index + segments; }
        int last_force() const { return index + segments - 1; }
        int size() const { return 2 * segments - 1; }
    };
    // the span's rows: z' of its forces and node speeds, given its ends' speed deviations
    static void span_rates(const Span& span, const double* z, double behind, double ahead,
                           double* zdot);

    std::vector<StandBlock> stands_;
    std::vector<Span> spans_;
    std::vector<int> back_span_, front_span_;         // per stand, an index into spans_ or -1
    std::vector<double> back_stress_, front_stress_;  // constant boundaries, Pa
    std::vector<double> bite_gain_;                   // per stand, empty: 1
    std::vector<double> span_length_;                 // the interstand spans' L_i, m
    int size_ = 0;
    BiteStatus status_ = BiteStatus::ok;
    int failed_stand_ = -1;
};

}  // namespace rollgap::core
