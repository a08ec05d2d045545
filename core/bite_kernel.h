#pragma once
// The roll-bite kernel of docs/model.md §1-4 for one trial neutral point: the bite's geometry and
// kinematics, the friction law, and the fixed-step RK4 integration of the pressure on each side.
// Internal to core: solve_roll_bite() (core/roll_bite.cpp) shoots on the neutral point with it in
// doubles; the bite sensitivities (core/bite_jacobian.cpp, docs/model.md §6.1) run the same
// arithmetic once more in dual numbers (core/dual.h) at the converged neutral point. One text for
// both, so that the derivative is the derivative of exactly the discrete bite that is solved.

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/christensen_contact.h"
#include "core/dual.h"
#include "core/inlet_film.h"
#include "core/roll_bite.h"

namespace rollgap::core::bite_kernel {

inline Regime regime_of(double film_ratio) {
    if (film_ratio < 0.5) return Regime::boundary;
    if (film_ratio <= 3.0) return Regime::mixed;
    return Regime::full_film;
}

// A(H_t) in the selected model, with its derivative carried for a dual H_t.
inline double contact_of(ContactModel model, double film_ratio) {
    return contact_ratio(model, film_ratio);
}
template <int N>
Dual<N> contact_of(ContactModel model, const Dual<N>& film_ratio) {
    const ContactRatioAndSlope a = contact_ratio_and_slope(model, film_ratio.v);
    return chain(film_ratio, a.ratio, a.slope);
}

// Everything about the bite that does not depend on the trial neutral point. T is double, or a
// dual number for the inputs the dynamics move (y1, y2, gap rate, h0, s_b, s_f); the radius, the
// roll speed and the material are constants of a linearisation.
template <class T>
struct Bite {
    T y1, y2;
    double a, v, sigma;
    T back, front;
    double width;
    T gap_rate;
    T contact_length, inlet_angle;
    double asperity_stress;  // tau_a = m_a sigma / 2
    double rq;               // composite roughness
    T fixed_film;            // h0 > 0, or <= 0 for the steady film h00(u1)
    const Scenario* s;
    int intervals;

    T thickness(const T& x) const { return y2 + x * x / a; }
};

// The bite of `state` under `s` (the inputs not yet checked: solve_roll_bite() does that).
inline Bite<double> bite_of(const Scenario& s, const BiteState& state) {
    Bite<double> b;
    b.s = &s;
    b.y1 = state.entry_thickness_or(s.strip.entry_thickness);
    b.y2 = state.exit_thickness;
    b.a = state.roll_radius > 0.0 ? state.roll_radius : s.rolls.radius;
    b.v = s.rolls.speed;
    b.sigma = s.strip.flow_stress;
    b.back = state.back_tension;
    b.front = state.front_tension;
    b.width = s.strip.width;
    b.gap_rate = state.gap_rate;
    b.asperity_stress = s.friction.asperity_factor * 0.5 * s.strip.flow_stress;
    b.rq = std::hypot(s.roughness.roll_rq, s.roughness.strip_rq);
    b.fixed_film = state.inlet_film;
    b.intervals = std::max(2, s.numerics.bite_intervals);
    b.contact_length = 0.0;
    b.inlet_angle = 0.0;
    return b;
}

// The same bite with every input a constant of scalar type T (their derivatives zero).
template <class T>
Bite<T> lifted(const Bite<double>& b) {
    Bite<T> out;
    out.y1 = b.y1;
    out.y2 = b.y2;
    out.a = b.a;
    out.v = b.v;
    out.sigma = b.sigma;
    out.back = b.back;
    out.front = b.front;
    out.width = b.width;
    out.gap_rate = b.gap_rate;
    out.contact_length = b.contact_length;
    out.inlet_angle = b.inlet_angle;
    out.asperity_stress = b.asperity_stress;
    out.rq = b.rq;
    out.fixed_film = b.fixed_film;
    out.s = b.s;
    out.intervals = b.intervals;
    return out;
}

// x_w = sqrt(a (y1 - y2)) and theta = x_w / a, once y1 > y2 is known.
template <class T>
void set_contact(Bite<T>& b) {
    using std::sqrt;
    b.contact_length = sqrt(b.a * (b.y1 - b.y2));
    b.inlet_angle = b.contact_length / b.a;
}

// Kinematics along one side for one trial neutral point: u, h, A at the RK4 nodes and
// midpoints. They depend on x only (not on p), so they are computed once per side.
template <class T>
struct SidePoint {
    T x, y, u, slip, film, film_ratio, contact;
};

// The traction on one side: the asperity part always opposes the slip, the fluid part is
// Newtonian with Barus viscosity capped by the limiting shear lambda_L p (evaluated in log
// space: gamma p reaches ~700 and exp(gamma p) would overflow). Without the cap the bite
// viscosity is eta0 (docs/model.md §4). `direction` is +1 on the exit side (u > v), -1 on the
// entry side: the slip changes sign at the neutral point and only there.
template <class T>
struct FrictionLaw {
    const Scenario* s;
    double asperity_stress;

    T operator()(const SidePoint<T>& pt, const T& p, double direction) const {
        using std::abs;
        using std::exp;
        const Friction& f = s->friction;
        if (f.model == FrictionModel::coulomb) return direction * f.coulomb_coefficient * p;

        const T speed = abs(pt.slip);
        T fluid = 0.0;
        const Lubricant& lub = s->lubricant;
        if (speed > 0.0) {
            if (!lub.limiting_shear) {
                fluid = lub.viscosity * speed / pt.film;
            } else if (p > 0.0) {
                // Newtonian / cap = ratio exp(gamma p); compared through exp(-gamma p), which
                // underflows to 0 (cap wins) where exp(gamma p) would overflow.
                // Beyond gamma p = 700 and ratio 1e-290 the Newtonian stress exceeds the cap by
                // ~1e14: skip exp, whose underflow path is slow.
                const T cap = lub.limiting_shear_coefficient * p;
                const T ratio = lub.viscosity * speed / (pt.film * cap);
                const T gp = lub.pressure_viscosity * p;
                if (gp > 700.0 && ratio > 1e-290) {
                    fluid = cap;
                } else {
                    const T threshold = exp(-gp);
                    fluid = ratio < threshold ? cap * (ratio / threshold) : cap;
                }
            }
        }
        return direction * (pt.contact * asperity_stress + (1.0 - pt.contact) * fluid);
    }
};

template <class T>
struct SideResult {
    bool finite = true;
    T end_pressure = 0.0;
    T integral_p = 0.0, integral_tau = 0.0, integral_abs_tau = 0.0;
    // The pressure fell below zero somewhere on the side: the strip has left the roll there (a
    // contact pressure cannot pull), a state outside the model (docs/model.md §4).
    bool pressure_negative = false;
};

template <class T>
struct Trial {
    T neutral_point, entry_speed, inlet_film;
    bool valid;
};

// The values of a dual pass: the same numbers a pass in doubles gives (core/dual.h computes the
// value with the double operations, in the same order).
template <int N>
SideResult<double> values_of(const SideResult<Dual<N>>& r) {
    return {r.finite,         r.end_pressure.v,     r.integral_p.v,
            r.integral_tau.v, r.integral_abs_tau.v, r.pressure_negative};
}
template <int N>
Trial<double> values_of(const Trial<Dual<N>>& t) {
    return {t.neutral_point.v, t.entry_speed.v, t.inlet_film.v, t.valid};
}

template <class T>
class BiteSolver {
public:
    explicit BiteSolver(const Bite<T>& bite) : b_(bite), law_{bite.s, bite.asperity_stress} {}

    Trial<T> trial(const T& xn) const {
        using std::isfinite;
        Trial<T> t;
        t.neutral_point = xn;
        t.entry_speed = (b_.v * b_.thickness(xn) + (b_.contact_length - xn) * b_.gap_rate) / b_.y1;
        if (b_.fixed_film > 0.0) {
            t.inlet_film = b_.fixed_film;
        } else {
            const Lubricant& lub = b_.s->lubricant;
            t.inlet_film = wilson_walowit_film_of(lub.viscosity, lub.pressure_viscosity,
                                                  T(0.5 * (t.entry_speed + b_.v)), b_.inlet_angle,
                                                  b_.sigma, b_.back);
        }
        t.valid = isfinite(t.entry_speed) && isfinite(t.inlet_film) && t.inlet_film > 0.0 &&
                  b_.v + t.entry_speed > 0.0;
        return t;
    }

    // Geometry, speed and film at x; the slip and the contact ratio at `inside`, which is x
    // except at the end of a segment next to a jump (the neutral point, a jump of the paper's
    // contact fit), where the segment's one-sided limit is wanted (see integrate()).
    SidePoint<T> point(const Trial<T>& t, const T& x, const T& inside) const {
        SidePoint<T> pt;
        pt.x = x;
        pt.y = b_.thickness(x);
        pt.u = (t.entry_speed * b_.y1 - (b_.contact_length - x) * b_.gap_rate) / pt.y;
        // u - v factored so that it vanishes exactly at x_n (continuity with u(x_n) = v):
        // u - v = (x_n - x) (v (x_n + x) / a - dyc/dt) / y.
        const T& xn = t.neutral_point;
        pt.slip =
            (xn - inside) * (b_.v * (xn + inside) / b_.a - b_.gap_rate) / b_.thickness(inside);
        pt.film = film_at(t, pt.u);
        pt.film_ratio = pt.film / b_.rq;
        T contact_film_ratio = pt.film_ratio;
        if (inside != x) {
            const T u_inside =
                (t.entry_speed * b_.y1 - (b_.contact_length - inside) * b_.gap_rate) /
                b_.thickness(inside);
            contact_film_ratio = film_at(t, u_inside) / b_.rq;
        }
        pt.contact = b_.s->friction.model == FrictionModel::mixed
                         ? contact_of(b_.s->friction.contact, contact_film_ratio)
                         : T(0.0);
        return pt;
    }

    // eq. (15)
    T film_at(const Trial<T>& t, const T& u) const {
        return t.inlet_film * (b_.v + t.entry_speed) / (b_.v + u);
    }

    // Where the paper's fit (26) jumps (H_t = 0.5 and 1.5) inside (lo, hi). H_t(x) = c means
    // v + u(x) = h0 (v + u1) / (c Rq) = v + U, and with continuity u y = u1 y1 - (x_w - x) dyc/dt
    // that is the quadratic (U / a) x^2 - dyc/dt x + U y2 - u1 y1 + x_w dyc/dt = 0.
    int contact_jumps(const Trial<T>& t, const T& lo, const T& hi, T out[4]) const {
        using std::sqrt;
        int count = 0;
        if (b_.s->friction.model != FrictionModel::mixed ||
            b_.s->friction.contact != ContactModel::paper_fit) {
            return count;
        }
        for (double c : {0.5, 1.5}) {
            const T U = t.inlet_film * (b_.v + t.entry_speed) / (c * b_.rq) - b_.v;
            const T qa = U / b_.a, qb = -b_.gap_rate;
            const T qc = U * b_.y2 - t.entry_speed * b_.y1 + b_.contact_length * b_.gap_rate;
            T roots[2];
            int n = 0;
            if (qa == 0.0) {
                if (qb != 0.0) roots[n++] = -qc / qb;
            } else {
                const T disc = qb * qb - 4 * qa * qc;
                if (disc >= 0.0) {
                    const T root = sqrt(disc);
                    // copysign(root, qb), -0 included
                    const T q = -0.5 * (qb + (std::signbit(value_of(qb)) ? -root : root));
                    roots[n++] = q / qa;
                    if (q != 0.0) roots[n++] = qc / q;
                }
            }
            for (int i = 0; i < n; ++i) {
                if (roots[i] > lo && roots[i] < hi) out[count++] = roots[i];
            }
        }
        for (int i = 1; i < count; ++i) {  // at most four: insertion sort
            for (int j = i; j > 0 && out[j] < out[j - 1]; --j) std::swap(out[j], out[j - 1]);
        }
        return count;
    }

    // dp/dx = (sigma y' + 2 tau) / y, eq. (36) with y' = 2x / a.
    T slope(const SidePoint<T>& pt, const T& tau) const {
        return (b_.sigma * 2.0 * pt.x / b_.a + 2.0 * tau) / pt.y;
    }

    // Classical RK4 with a fixed number of steps from x_start to x_end (per segment between
    // jumps of the contact law): the same steps for the same inputs, so the solution is a smooth,
    // repeatable function of them. The integrals of p, tau and |tau| ride along as quadratures of
    // the same stages. `record` (doubles only) keeps the points for the distributions.
    SideResult<T> integrate(const Trial<T>& t, const T& x_start, const T& x_end, const T& p_start,
                            double direction, std::vector<BitePoint>* record) const {
        using std::abs;
        using std::isfinite;
        SideResult<T> r;
        T p = p_start;
        if (p < 0.0) r.pressure_negative = true;  // a tension above the flow stress
        auto emit = [&](const SidePoint<T>& pt, const T& pressure) {
            if constexpr (std::is_same_v<T, double>) {
                if (!record) return;
                record->push_back({pt.x, pressure, law_(pt, pressure, direction), pt.film,
                                   pt.film_ratio, pt.contact, pt.u, pt.y,
                                   regime_of(pt.film_ratio)});
            }
        };
        emit(point(t, x_start, x_start), p);
        if (x_end == x_start) {  // an empty side: the neutral point sits at the bite's end
            r.end_pressure = p;
            return r;
        }

        T jumps[4];
        const int jump_count = contact_jumps(t, x_start < x_end ? x_start : x_end,
                                             x_start < x_end ? x_end : x_start, jumps);
        T bounds[6];
        int segments = 0;
        bounds[0] = x_start;
        for (int j = 0; j < jump_count; ++j)
            bounds[++segments] = x_end > x_start ? jumps[j] : jumps[jump_count - 1 - j];
        bounds[++segments] = x_end;

        const int n = b_.intervals;
        for (int seg = 0; seg < segments; ++seg) {
            const T a = bounds[seg], b = bounds[seg + 1];
            const T step = (b - a) / n;
            // A segment's ends next to a jump take the segment's one-sided limit, a billionth of a
            // step inside. At the neutral point the fluid stress jumps from +cap to -cap through a
            // layer of width ~ lambda_L p h exp(-gamma p) / (eta0 |d(u - v)/dx|), far below double
            // resolution at the printed gamma; where the layer is resolved this is the continuous
            // value. At a jump of the paper's fit, A takes the branch of the segment.
            SidePoint<T> left = point(t, a, seg == 0 ? a : T(a + 1e-9 * step));
            if (seg > 0) emit(left, p);
            for (int i = 0; i < n; ++i) {
                const T x_mid = a + (i + 0.5) * step;
                const bool last = i + 1 == n;
                const T x_right = last ? b : T(a + (i + 1) * step);
                const SidePoint<T> mid = point(t, x_mid, x_mid);
                const SidePoint<T> right = point(t, x_right, last ? T(b - 1e-9 * step) : x_right);
                if (!(b_.v + mid.u > 0.0) || !(b_.v + right.u > 0.0)) {
                    r.finite = false;
                    return r;
                }
                const T t1 = law_(left, p, direction);
                const T k1 = slope(left, t1);
                const T p2 = p + 0.5 * step * k1;
                const T t2 = law_(mid, p2, direction);
                const T k2 = slope(mid, t2);
                const T p3 = p + 0.5 * step * k2;
                const T t3 = law_(mid, p3, direction);
                const T k3 = slope(mid, t3);
                const T p4 = p + step * k3;
                const T t4 = law_(right, p4, direction);
                const T k4 = slope(right, t4);

                r.integral_p += step * (p + 2.0 * p2 + 2.0 * p3 + p4) / 6.0;
                r.integral_tau += step * (t1 + 2.0 * t2 + 2.0 * t3 + t4) / 6.0;
                r.integral_abs_tau +=
                    step * (abs(t1) + 2.0 * abs(t2) + 2.0 * abs(t3) + abs(t4)) / 6.0;

                p += step * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0;
                if (p < 0.0) r.pressure_negative = true;
                left = right;
                emit(left, p);
            }
        }
        r.end_pressure = p;
        r.finite = isfinite(p) && isfinite(r.integral_p);
        return r;
    }

    SideResult<T> exit_side(const Trial<T>& t, std::vector<BitePoint>* record = nullptr) const {
        return integrate(t, T(0.0), t.neutral_point, T(b_.sigma - b_.front), +1.0, record);
    }
    SideResult<T> entry_side(const Trial<T>& t, std::vector<BitePoint>* record = nullptr) const {
        return integrate(t, b_.contact_length, t.neutral_point, T(b_.sigma - b_.back), -1.0,
                         record);
    }

    // Pressure jump at the trial neutral point: entry-side pressure minus exit-side pressure.
    // NaN flags an inconsistent state.
    T residual(const T& xn) const {
        const Trial<T> t = trial(xn);
        if (!t.valid) return std::nan("");
        const SideResult<T> exit = exit_side(t);
        const SideResult<T> entry = entry_side(t);
        if (!exit.finite || !entry.finite) return std::nan("");
        return entry.end_pressure - exit.end_pressure;
    }

private:
    Bite<T> b_;
    FrictionLaw<T> law_;
};

}  // namespace rollgap::core::bite_kernel
