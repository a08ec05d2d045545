#include "core/mill/mill_critical_speed.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>

#include "core/chatter_type.h"
#include "core/mill/mill_delay.h"
#include "core/mill/mill_model.h"
#include "core/mill/mill_regenerative.h"
#include "core/parallel_for.h"

namespace rollgap::core {

std::vector<double> mill_participation(const Mill& mill, const Eigen::VectorXcd& z) {
    std::vector<double> shares(static_cast<std::size_t>(mill.size()), 0.0);
    double total = 0.0;
    for (int i = 0; i < mill.size(); ++i) {
        const auto& masses = mill.stands[static_cast<std::size_t>(i)].structure.mass;
        double energy = 0.0;
        for (int k = 0; k < 6; ++k) {
            const Eigen::Index at = StandBlock::state_size * i + k;
            if (at < z.size()) energy += masses[static_cast<std::size_t>(k)] * std::norm(z(at));
        }
        shares[static_cast<std::size_t>(i)] = energy;
        total += energy;
    }
    if (total > 0.0)
        for (double& share : shares) share /= total;
    return shares;
}

CrossingValidity crossing_validity(const Mill& mill, const MillSteadyState& steady,
                                   double frequency_Hz) {
    CrossingValidity out;
    const double omega = 2.0 * std::numbers::pi * frequency_Hz;
    const double c = std::sqrt(mill.youngs_modulus / mill.strip_density);
    // under `segments` each segment is a spring of length L / n (§12.1): its error is judged
    const double segments =
        mill.span_model == SpanModel::segments ? static_cast<double>(mill.span_segments) : 1.0;
    for (double length : mill.span_length) {
        const double x = omega * length / c;
        out.span_wave_number.push_back(x);
        const double xs = x / segments;
        const double error = xs > 0.0 ? 1.0 - xs / std::tan(xs) : 0.0;
        out.spring_law_error.push_back(error);
        // beyond x = pi/2 the spring's sign is wrong (tan < 0): outside as well
        if (!(error <= 0.25) || xs >= 0.5 * std::numbers::pi) out.spring_law_valid = false;
    }
    for (const MillStandState& stand : steady.stands) {
        const double ratio = stand.entry_speed > 0.0
                                 ? stand.bite.contact_length / stand.entry_speed * frequency_Hz
                                 : 0.0;
        out.bite_transit_ratio.push_back(ratio);
        if (ratio > 0.2) out.quasi_static_bite_valid = false;
    }
    return out;
}

MillTransfer mill_transfer(const Mill& mill, std::vector<double> gains) {
    MillTransfer out;
    out.steady = mill_steady_state(mill);
    if (out.steady.status != MillSteadyStatus::ok) return out;
    MillModel model(mill, out.steady);
    if (model.status() != BiteStatus::ok) return out;
    model.set_bite_gains(std::move(gains));
    const MillLinearisation lin = model.linearise(model.equilibrium());
    if (lin.status != DynamicsStatus::ok) return out;
    out.transfer = transport_transfer(lin);
    out.ok = out.transfer.ok;
    return out;
}

const char* to_string(MillCrossingKind kind) {
    switch (kind) {
        case MillCrossingKind::frozen: return "frozen";
        case MillCrossingKind::delay_independent: return "delay_independent";
        case MillCrossingKind::nominal_delay: return "nominal_delay";
    }
    return "frozen";
}

namespace {

Mill at_speed(const Mill& mill, double speed) {
    Mill m = mill;
    m.speed = speed;
    return m;
}

using Linearised = MillTransfer;

Linearised linearised(const Mill& mill, std::vector<double> gains = {}) {
    return mill_transfer(mill, std::move(gains));
}

// Frequency, moving and feeding stands, band and validity of a crossing at its speed, from a
// state vector z; `growth` measures the crossing on a transfer (its root's real part, or rho),
// differentiated in each stand's bite gain by central differences (kappa = +-1e-3).
// The 2N linearisations run on the control's threads (each writes its own value).
void describe(MillCrossing& crossing, const Mill& mill, double frequency_Hz,
              const Eigen::VectorXcd& z,
              const std::function<double(const TransportTransfer&)>& growth,
              const Control& control = {}) {
    crossing.frequency_Hz = frequency_Hz;
    crossing.band = chatter_band(frequency_Hz);
    crossing.participation = mill_participation(mill, z);
    crossing.moving_stand = static_cast<int>(
        std::max_element(crossing.participation.begin(), crossing.participation.end()) -
        crossing.participation.begin());
    Vector6c q = Vector6c::Zero();
    for (int k = 0; k < 6; ++k) {
        const Eigen::Index at = StandBlock::state_size * crossing.moving_stand + k;
        if (at < z.size()) q(k) = z(at);
    }
    crossing.chatter = classify_chatter(q, frequency_Hz);
    const Mill m = at_speed(mill, crossing.speed);
    const MillSteadyState steady = mill_steady_state(m);
    crossing.validity = crossing_validity(mill, steady, frequency_Hz);
    constexpr double kappa = 1e-3;
    std::vector<double> value(2 * static_cast<std::size_t>(mill.size()), 0.0);  // (+, -) per stand
    parallel_for(2 * mill.size(), control, [&](int k) {
        const int i = k / 2, side = k % 2;
        std::vector<double> gains(static_cast<std::size_t>(mill.size()), 1.0);
        gains[static_cast<std::size_t>(i)] += side == 0 ? kappa : -kappa;
        const Linearised l = linearised(m, std::move(gains));
        value[static_cast<std::size_t>(k)] = l.ok ? growth(l.transfer) : std::nan("");
    });
    for (int i = 0; i < mill.size(); ++i) {
        const double plus = value[2 * static_cast<std::size_t>(i)];
        const double minus = value[2 * static_cast<std::size_t>(i) + 1];
        crossing.feeding_sensitivity.push_back((plus - minus) / (2.0 * kappa));
    }
    double best = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < mill.size(); ++i) {
        const double x = crossing.feeding_sensitivity[static_cast<std::size_t>(i)];
        if (x > best) {
            best = x;
            crossing.feeding_stand = i;
        }
    }
}

// The frozen response to the loop's worst input at the margin's frequency: u = D^-1 v, v the
// top right singular vector of D M D^-1.
Eigen::VectorXcd margin_response(const TransportTransfer& transfer,
                                 const RegenerativeMargin& margin) {
    const Eigen::Index p = transfer.spans();
    if (p == 0 || margin.transfer.rows() != p) return Eigen::VectorXcd::Zero(transfer.poles.size());
    const Eigen::VectorXcd u = margin_worst_input(margin);
    return transport_response(transfer, {0.0, 2.0 * std::numbers::pi * margin.frequency_Hz}, u);
}

// The top of the model's range at a steady state: the largest frequency at which every span's
// spring law and every stand's quasi-static bite are valid (both errors grow with f), by
// bisection to 1e-9 of it; 0 when even 1e-3 Hz is outside.
double valid_frequency_Hz(const Mill& mill, const MillSteadyState& steady) {
    const auto valid = [&](double f) { return crossing_validity(mill, steady, f).valid(); };
    if (!valid(1e-3)) return 0.0;
    double lo = 1e-3, hi = 2e-3;
    while (valid(hi)) {
        lo = hi;
        hi *= 2.0;
        if (hi > 1e9) return lo;
    }
    while (hi - lo > 1e-9 * hi) {
        const double mid = 0.5 * (lo + hi);
        (valid(mid) ? lo : hi) = mid;
    }
    return lo;
}

// A nominal-delay crossing described by its root s at the crossing's speed.
void describe_root(MillCrossing& c, const Mill& mill, const TransportTransfer& transfer,
                   std::complex<double> root, const Control& control) {
    describe(
        c, mill, root.imag() / (2.0 * std::numbers::pi), delay_root_vector(transfer, root),
        [root](const TransportTransfer& t) {
            const DelayRoot moved = delay_root(t, root);
            return moved.converged ? moved.s.real() : std::nan("");
        },
        control);
}

// The first speed from `start` upwards where count_at turns positive: blocks of speeds in
// parallel (at least block_speeds of them), in order, each step step_at(the block's first
// speed), at most 400 steps (with `prefetch(block start, step)` as one more task beside each
// block's counts, where given), then
// bisection between the last zero and the first positive count to the search's tolerance.
// Fills c's status and speed; false when cancelled.
bool first_positive(MillCrossing& c, const std::function<int(double)>& count_at, double start,
                    const std::function<double(double)>& step_at,
                    const CriticalSpeedOptions& options, const Control& control,
                    int block_speeds = 0,
                    const std::function<void(double, double)>& prefetch = {}) {
    const int block = std::max({2, control.thread_budget(), block_speeds});
    constexpr int max_steps = 400;
    double stable_speed = -1.0, unstable_speed = -1.0;
    double block_start = start;
    for (int begin = 0; begin < max_steps && unstable_speed < 0.0; begin += block) {
        if (control.should_stop()) {
            c.status = CriticalSpeedStatus::cancelled;
            return false;
        }
        const double step = step_at(block_start);
        std::vector<int> counts(static_cast<std::size_t>(block), -1);
        const int ahead = prefetch ? 1 : 0;  // the prefetch first: the longest task
        parallel_for(block + ahead, control, [&](int task) {
            if (task < ahead) return prefetch(block_start, step);
            const int k = task - ahead;
            const double v = block_start + k * step;
            if (v <= options.speed_max) counts[static_cast<std::size_t>(k)] = count_at(v);
        });
        for (int k = 0; k < block; ++k) {
            const double v = block_start + k * step;
            if (v > options.speed_max) break;
            const int n = counts[static_cast<std::size_t>(k)];
            if (n == 0) {
                stable_speed = v;
            } else if (n > 0) {
                unstable_speed = v;
                break;
            }
        }
        block_start += block * step;
        if (block_start > options.speed_max) break;
    }
    if (unstable_speed < 0.0) {
        c.status = CriticalSpeedStatus::stable_in_range;
    } else if (stable_speed < 0.0 || stable_speed > unstable_speed) {
        c.status = CriticalSpeedStatus::unstable_at_lower_bound;
        c.speed = unstable_speed;
    } else {
        double lo = stable_speed, hi = unstable_speed;
        while (hi - lo > options.relative_tolerance * lo) {
            const double mid = 0.5 * (lo + hi);
            const int n = count_at(mid);
            if (n == 0) lo = mid;
            else hi = mid;
        }
        c.status = CriticalSpeedStatus::found;
        c.speed = hi;
    }
    return true;
}

}  // namespace

double mill_band_screen_speed(const Mill& mill, double start, CriticalSpeedOptions options,
                              const Control& control) {
    constexpr double threshold = 0.9;
    options.speed_min = start;
    if (!(options.speed_max > start)) return start;
    const auto at = [&mill](double speed, bool) {
        SpeedStability p;
        p.speed = speed;
        const Mill m = at_speed(mill, speed);
        const Linearised l = linearised(m);
        p.steady_status =
            l.steady.status == MillSteadyStatus::ok ? BiteStatus::ok : BiteStatus::skidding;
        if (!l.ok) return p;
        p.status = DynamicsStatus::ok;
        const double f_valid = valid_frequency_Hz(m, l.steady);
        if (l.transfer.frozen_max_real_part >= 0.0) {
            p.max_real_part = 1.0;
        } else if (f_valid > 1e-2) {
            RegenerativeOptions band;
            band.frequency_min_Hz = 1e-2;
            band.frequency_max_Hz = f_valid;
            band.grid = 200;
            p.max_real_part = regenerative_margin(l.transfer, band).margin - threshold;
        } else {
            p.max_real_part = -threshold;  // an empty band
        }
        p.stable = p.max_real_part < 0.0;
        return p;
    };
    const CriticalSpeedResult r = critical_speed_search(at, options, control);
    switch (r.status) {
        case CriticalSpeedStatus::found: return std::max(start, r.critical_speed);
        case CriticalSpeedStatus::stable_in_range: return options.speed_max;
        default: return start;
    }
}

MillRootDescription describe_rightmost_root(const Mill& mill, const MillSpeedStability& at) {
    MillRootDescription out;
    if (at.steady.status != MillSteadyStatus::ok) return out;
    const Linearised l = linearised(mill);
    if (!l.ok) return out;
    // The roots inside the model's band at this speed, counted as the nominal-delay search
    // counts them (docs/model.md §12.7): what the headline's "stable" means at this speed.
    out.band_top_Hz = valid_frequency_Hz(mill, l.steady);
    if (out.band_top_Hz > 0.0) {
        const BandRootCount band =
            band_root_count(l.transfer, 2.0 * std::numbers::pi * out.band_top_Hz, 0.0);
        if (band.ok) {
            out.band_count = band.count;
            out.band_count_error = band.integer_error;
        }
    } else {
        out.band_count = 0;  // an empty band holds no root
    }
    if (!at.rightmost.found) return out;
    out.found = true;
    out.verified = at.rightmost.verified;
    out.s = at.rightmost.root.s;
    MillCrossing& c = out.described;
    c.kind = MillCrossingKind::nominal_delay;
    c.status = CriticalSpeedStatus::found;
    c.speed = mill.speed;
    const std::complex<double> root = out.s;
    describe(c, mill, root.imag() / (2.0 * std::numbers::pi), delay_root_vector(l.transfer, root),
             [root](const TransportTransfer& t) {
                 const DelayRoot moved = delay_root(t, root);
                 return moved.converged ? moved.s.real() : std::nan("");
             });
    return out;
}

MillCriticalSpeeds mill_critical_speeds(const Mill& mill, const CriticalSpeedOptions& options,
                                        const Control& control) {
    MillCriticalSpeeds out;
    CriticalSpeedOptions search = options;
    search.stop_at_crossing = true;

    // The frozen and the delay-independent searches side by side (each its own crossing; nested
    // loops share the control's threads), then first_any and the band's search side by side.
    // frozen: A0 alone
    const auto frozen_search = [&] {
        MillCrossing& c = out.frozen;
        c.kind = MillCrossingKind::frozen;
        const CriticalSpeedResult r = mill_frozen_critical_speed(mill, search, control);
        c.status = r.status;
        if (r.status == CriticalSpeedStatus::found) {
            c.speed = r.critical_speed;
            const Linearised l = linearised(at_speed(mill, c.speed));
            // the crossing eigenvector: A0's eigenvalue nearest the crossing mode's
            Eigen::VectorXcd z = Eigen::VectorXcd::Zero(1);
            if (l.ok) {
                Eigen::Index best = 0;
                for (Eigen::Index k = 1; k < l.transfer.poles.size(); ++k)
                    if (std::abs(l.transfer.poles(k) - r.unstable_mode.eigenvalue) <
                        std::abs(l.transfer.poles(best) - r.unstable_mode.eigenvalue))
                        best = k;
                z = l.transfer.modes.col(best);
            }
            const std::complex<double> root = r.unstable_mode.eigenvalue;
            describe(
                c, mill, r.unstable_mode.frequency_Hz, z,
                [root](const TransportTransfer& t) {
                    Eigen::Index best = 0;
                    for (Eigen::Index k = 1; k < t.poles.size(); ++k)
                        if (std::abs(t.poles(k) - root) < std::abs(t.poles(best) - root)) best = k;
                    return t.poles(best).real();
                },
                control);
        }
    };

    // delay-independent: g = rho - 1 while A0 is stable
    const auto delay_independent_search = [&] {
        MillCrossing& c = out.delay_independent;
        c.kind = MillCrossingKind::delay_independent;
        const auto at = [&mill](double speed, bool) {
            SpeedStability p;
            p.speed = speed;
            const Linearised l = linearised(at_speed(mill, speed));
            p.steady_status =
                l.steady.status == MillSteadyStatus::ok ? BiteStatus::ok : BiteStatus::skidding;
            if (!l.ok) return p;  // status solver_failure: not usable
            p.status = DynamicsStatus::ok;
            if (l.transfer.frozen_max_real_part >= 0.0) {
                p.max_real_part = 1.0;
            } else {
                const RegenerativeMargin margin = regenerative_margin(l.transfer);
                p.max_real_part = margin.margin - 1.0;
                p.least_damped.frequency_Hz = margin.frequency_Hz;
                p.least_damped.eigenvalue = {0.0, 2.0 * std::numbers::pi * margin.frequency_Hz};
            }
            p.stable = p.max_real_part < 0.0;
            return p;
        };
        const CriticalSpeedResult r = critical_speed_search(at, search, control);
        c.status = r.status;
        if (r.status == CriticalSpeedStatus::found) {
            c.speed = r.critical_speed;
            const Linearised l = linearised(at_speed(mill, c.speed));
            if (l.ok) {
                const RegenerativeMargin margin = regenerative_margin(l.transfer);
                const std::complex<double> at{0.0, 2.0 * std::numbers::pi * margin.frequency_Hz};
                describe(
                    c, mill, margin.frequency_Hz, margin_response(l.transfer, margin),
                    [at](const TransportTransfer& t) { return structured_bound(t.at(at)); },
                    control);
            }
        }
    };
    parallel_for(2, control, [&](int k) {
        if (k == 0) frozen_search();
        else delay_independent_search();
    });

    // nominal delays: from the delay-independent speed up. first_any: the first speed where any
    // root crosses, in steps of half a lobe period at the delay-independent frequency;
    // nominal_delay: the first where a root inside the model's band does (the band count at
    // Omega = 2 pi f_valid of the speed), in steps of half a lobe period at f_valid
    {
        MillCrossing& any = out.first_any;
        MillCrossing& c = out.nominal_delay;
        any.kind = c.kind = MillCrossingKind::nominal_delay;
        const MillCrossing& di = out.delay_independent;
        if (di.status == CriticalSpeedStatus::stable_in_range ||
            di.status == CriticalSpeedStatus::no_steady_state ||
            di.status == CriticalSpeedStatus::cancelled) {
            any.status = c.status = di.status;  // stable for every delay, or nothing to start from
        } else {
            const double start =
                di.status == CriticalSpeedStatus::found ? di.speed : options.speed_min;
            const auto tau_max_of = [](const TransportTransfer& t) {
                double tau_max = 0.0;
                for (double tau : t.delay) tau_max = std::max(tau_max, tau);
                return tau_max;
            };
            const Linearised first = linearised(at_speed(mill, start));
            const double f = di.frequency_Hz > 0.0 ? di.frequency_Hz : 100.0;
            const double lobe = start / (f * std::max(tau_max_of(first.transfer), 1e-9));
            any.lobe_period = lobe;
            // first_any's counts in blocks of 16 speeds, each block stepping half a lobe period at
            // its first speed (the lobe widens as V^2: tau ~ 1/V): the line's loud stretches
            // (gain >= 0.8) at each block's first speed and the next's, their union reused by the
            // counts between, which sample only there (docs/model.md §12.7: M has no delays and
            // moves by ~0.02 % a step; every count checks its gaps' ends at its own speed). The
            // profile at the end of the block after this one is computed beside this block's
            // counts (its step is known from this block's end), and each profile's linearisation
            // serves that speed's count: the scan's speeds and counts are the serial ones.
            constexpr int any_block = 16;
            constexpr double loud_threshold = 0.8;
            struct Profile {
                Linearised l;
                LoudStretches loud;
                double step = 0.0;  // half a lobe period here at f
            };
            const auto profile_at = [&](double speed) {
                auto out = std::make_shared<Profile>();
                out->l = linearised(at_speed(mill, speed));
                if (out->l.ok) out->loud = loud_stretches(out->l.transfer, 0.0, loud_threshold);
                const double tau = out->l.ok ? tau_max_of(out->l.transfer) : 0.0;
                out->step = tau > 0.0 ? 0.5 * speed / (f * tau) : 0.5 * lobe;
                return std::shared_ptr<const Profile>(std::move(out));
            };
            std::mutex profile_mutex;
            std::map<double, std::shared_ptr<const Profile>> profiles;  // by speed, exact
            const auto cached_profile = [&](double speed) {
                {
                    const std::lock_guard lock(profile_mutex);
                    const auto it = profiles.find(speed);
                    if (it != profiles.end()) return it->second;
                }
                std::shared_ptr<const Profile> made = profile_at(speed);
                const std::lock_guard lock(profile_mutex);
                return profiles.emplace(speed, std::move(made)).first->second;
            };
            struct LoudBlock {
                double from = -1.0, to = -1.0;
                LoudStretches loud;
            };
            auto loud_block = std::make_shared<const LoudBlock>();  // set between blocks only
            const auto any_step = [&](double block_start) {
                const std::shared_ptr<const Profile> first = cached_profile(block_start);
                const double step = first->step;
                auto next = std::make_shared<LoudBlock>();
                next->from = block_start;
                next->to = block_start + any_block * step;  // the next block's start
                next->loud = loud_union(first->loud, cached_profile(next->to)->loud);
                loud_block = std::move(next);
                const std::lock_guard lock(profile_mutex);  // profiles behind this block: done
                profiles.erase(profiles.begin(), profiles.lower_bound(block_start));
                return step;
            };
            const auto any_prefetch = [&](double block_start, double step) {
                const double next_start = block_start + any_block * step;
                const double next_step = cached_profile(next_start)->step;
                if (next_start + any_block * next_step <= options.speed_max)
                    cached_profile(next_start + any_block * next_step);
            };
            const auto count_at = [&](double speed) {
                std::shared_ptr<const Profile> kept;
                {
                    const std::lock_guard lock(profile_mutex);
                    const auto it = profiles.find(speed);
                    if (it != profiles.end()) kept = it->second;
                }
                const Linearised fresh = kept ? Linearised{} : linearised(at_speed(mill, speed));
                const Linearised& l = kept ? kept->l : fresh;
                if (!l.ok) return -1;
                const LoudBlock& block = *loud_block;
                const DelayRootCount n = speed >= block.from && speed <= block.to
                                             ? nominal_delay_root_count(l.transfer, 0.0, block.loud)
                                             : nominal_delay_root_count(l.transfer, 0.0);
                return n.ok ? n.count : -1;
            };
            // the linearisation and f_valid at a speed; the step's, taken at each block's first
            // speed, is kept for that speed's band count (one linearisation fewer a block)
            struct BandPoint {
                Linearised l;
                double f_valid = 0.0;
            };
            const auto band_point = [&mill](double speed) {
                auto p = std::make_shared<BandPoint>();
                p->l = linearised(at_speed(mill, speed));
                if (p->l.ok) p->f_valid = valid_frequency_Hz(at_speed(mill, speed), p->l.steady);
                return std::shared_ptr<const BandPoint>(std::move(p));
            };
            std::mutex kept_mutex;
            double kept_speed = -1.0;
            std::shared_ptr<const BandPoint> kept;
            const auto band_count_at = [&](double speed) {
                std::shared_ptr<const BandPoint> p;
                {
                    const std::lock_guard lock(kept_mutex);
                    if (kept && kept_speed == speed) p = kept;
                }
                if (!p) p = band_point(speed);
                if (!p->l.ok) return -1;
                if (!(p->f_valid > 0.0)) return 0;  // an empty band
                const BandRootCount n =
                    band_root_count(p->l.transfer, 2.0 * std::numbers::pi * p->f_valid, 0.0);
                return n.ok ? n.count : -1;
            };
            const auto band_step = [&](double speed) {
                const std::shared_ptr<const BandPoint> p = band_point(speed);
                {
                    const std::lock_guard lock(kept_mutex);
                    kept_speed = speed;
                    kept = p;
                }
                const double tau_max = p->l.ok ? tau_max_of(p->l.transfer) : 0.0;
                // half a lobe period at f_valid; half the first one's where it is not defined
                if (!(p->f_valid > 0.0) || !(tau_max > 0.0)) return 0.5 * lobe;
                return 0.5 * speed / (p->f_valid * tau_max);
            };
            const auto any_search = [&] {
                if (!first_positive(any, count_at, start, any_step, options, control, any_block,
                                    any_prefetch))
                    return;
                if (any.status == CriticalSpeedStatus::found ||
                    any.status == CriticalSpeedStatus::unstable_at_lower_bound) {
                    const Linearised l = linearised(at_speed(mill, any.speed));
                    if (l.ok) {
                        const DelayRootCount n = nominal_delay_root_count(l.transfer, 0.0);
                        const RightmostDelayRoot r = rightmost_delay_root(l.transfer, n);
                        if (r.found) describe_root(any, mill, l.transfer, r.root.s, control);
                    }
                }
            };
            // The band's screen (docs/model.md §12.7): below the first speed where the
            // structured gain over the band's stretch of the axis reaches 0.9, no root crosses the
            // axis inside the band for any delays (A0 stable there), so the counted scan starts
            // there. A root that entered the band across its top edge before it is seen by the
            // first count; then the scan starts again from the delay-independent speed.
            const auto band_search = [&] {
                const double band_start = mill_band_screen_speed(mill, start, search, control);
                if (control.should_stop()) {
                    c.status = CriticalSpeedStatus::cancelled;
                    return;
                }
                if (!first_positive(c, band_count_at, band_start, band_step, options, control))
                    return;
                if (c.status == CriticalSpeedStatus::unstable_at_lower_bound &&
                    band_start > start &&
                    !first_positive(c, band_count_at, start, band_step, options, control))
                    return;
                if (c.status == CriticalSpeedStatus::found ||
                    c.status == CriticalSpeedStatus::unstable_at_lower_bound) {
                    const Linearised l = linearised(at_speed(mill, c.speed));
                    if (l.ok) {
                        const double f_valid =
                            valid_frequency_Hz(at_speed(mill, c.speed), l.steady);
                        if (f_valid > 0.0) {
                            const BandRootCount n =
                                band_root_count(l.transfer, 2.0 * std::numbers::pi * f_valid, 0.0);
                            const RightmostDelayRoot r = band_rightmost_root(l.transfer, n);
                            if (r.found) describe_root(c, mill, l.transfer, r.root.s, control);
                        }
                        // the lobe period at the crossing root's frequency (f_valid if none found)
                        const double f_lobe = c.frequency_Hz > 0.0 ? c.frequency_Hz : f_valid;
                        c.lobe_period = c.speed / (std::max(f_lobe, 1e-9) *
                                                   std::max(tau_max_of(l.transfer), 1e-9));
                    }
                }
            };
            parallel_for(2, control, [&](int k) {
                if (k == 0) any_search();
                else band_search();
            });
            // a cancelled search cancels the answer's other nominal-delay search too
            if (any.status == CriticalSpeedStatus::cancelled ||
                c.status == CriticalSpeedStatus::cancelled)
                any.status = c.status = CriticalSpeedStatus::cancelled;
        }
    }

    // the headline: the lowest found crossing inside the model's range
    const MillCrossing* crossings[] = {&out.frozen, &out.delay_independent, &out.nominal_delay};
    double lowest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const MillCrossing& c = *crossings[k];
        if (c.status == CriticalSpeedStatus::found && c.validity.valid() && c.speed < lowest) {
            lowest = c.speed;
            out.headline = k;
        }
    }
    for (int k = 0; k < 3; ++k) {
        const MillCrossing& c = *crossings[k];
        if (c.status == CriticalSpeedStatus::found && !c.validity.valid() && c.speed < lowest)
            out.outside_range_below.push_back(c.kind);
    }
    return out;
}

}  // namespace rollgap::core
