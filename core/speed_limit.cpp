#include "core/speed_limit.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>

#include "core/brent.h"
#include "core/parallel_for.h"
#include "core/propagation.h"
#include "core/roll_bite.h"

namespace rollgap::core {

const char* to_string(SpeedLimitKind kind) {
    switch (kind) {
        case SpeedLimitKind::chatter: return "chatter";
        case SpeedLimitKind::force: return "force";
        case SpeedLimitKind::torque: return "torque";
        case SpeedLimitKind::power: return "power";
        case SpeedLimitKind::skid: return "skid";
        case SpeedLimitKind::steady_state: return "steady_state";
    }
    return "steady_state";
}

const char* to_string(SpeedLimitStatus status) {
    switch (status) {
        case SpeedLimitStatus::ok: return "ok";
        case SpeedLimitStatus::no_window: return "no_window";
        case SpeedLimitStatus::no_operating: return "no_operating";
        case SpeedLimitStatus::cancelled: return "cancelled";
    }
    return "no_window";
}

SteadyFigures steady_figures(const Scenario& s, double speed) {
    SteadyFigures out;
    out.speed = speed;
    Scenario at = s;
    at.rolls.speed = speed;
    BiteOptions options;
    options.distributions = false;
    const BiteResult bite = solve_roll_bite(at, steady_bite_state(at), options);
    if (bite.status != BiteStatus::ok) return out;
    out.ok = true;
    out.force = bite.force;
    out.torque = std::abs(bite.torque);
    // both work rolls turn at v / a (the rigid radius: the roll's own angular speed)
    out.power = 2.0 * out.torque * speed / s.rolls.radius;
    out.forward_slip = bite.forward_slip;
    return out;
}

namespace {

using Interval = std::pair<double, double>;

// The speeds a predicate permits over the grid, each change of its answer between two grid
// speeds located by bisection to `tolerance` relative.
std::vector<Interval> permitted_intervals(const std::vector<double>& grid,
                                          const std::vector<bool>& on_grid,
                                          const std::function<bool(double)>& permits,
                                          double tolerance) {
    std::vector<Interval> out;
    double start = on_grid.front() ? grid.front() : -1.0;
    for (std::size_t k = 0; k + 1 < grid.size(); ++k) {
        if (on_grid[k] == on_grid[k + 1]) continue;
        double lo = grid[k], hi = grid[k + 1];  // permits(lo) == on_grid[k]
        while (hi - lo > tolerance * hi) {
            const double mid = 0.5 * (lo + hi);
            (permits(mid) == on_grid[k] ? lo : hi) = mid;
        }
        if (on_grid[k]) {
            out.emplace_back(start, lo);  // the last permitted speed found
        } else {
            start = hi;
        }
    }
    if (on_grid.back()) out.emplace_back(start, grid.back());
    return out;
}

std::vector<Interval> intersect(const std::vector<Interval>& a, const std::vector<Interval>& b) {
    std::vector<Interval> out;
    std::size_t i = 0, j = 0;
    while (i < a.size() && j < b.size()) {
        const double lo = std::max(a[i].first, b[j].first);
        const double hi = std::min(a[i].second, b[j].second);
        if (lo <= hi) out.emplace_back(lo, hi);
        (a[i].second < b[j].second ? i : j) += 1;
    }
    return out;
}

// The interval holding v, else the nearest (the lower on a tie); nullptr when there is none.
const Interval* nearest(const std::vector<Interval>& intervals, double v) {
    const Interval* best = nullptr;
    double best_distance = std::numeric_limits<double>::infinity();
    for (const Interval& x : intervals) {
        const double distance = v < x.first ? x.first - v : v > x.second ? v - x.second : 0.0;
        if (distance < best_distance) {
            best_distance = distance;
            best = &x;
        }
    }
    return best;
}

}  // namespace

namespace speed_window_detail {

// A check's figure in SteadyFigures, and its margin there (>= 0 where it permits the speed).
double figure(const SteadyFigures& f, SpeedLimitKind kind) {
    switch (kind) {
        case SpeedLimitKind::force: return f.force;
        case SpeedLimitKind::torque: return f.torque;
        case SpeedLimitKind::power: return f.power;
        default: return f.forward_slip;
    }
}

double margin(const SteadyFigures& f, const SpeedCheck& check) {
    return check.kind == SpeedLimitKind::skid ? f.forward_slip - check.limit
                                              : check.limit - figure(f, check.kind);
}

bool all_ok(const std::vector<SteadyFigures>& figures) {
    return !figures.empty() &&
           std::all_of(figures.begin(), figures.end(), [](const SteadyFigures& f) { return f.ok; });
}

// Whether the figures permit the speed under `check`: the steady_state check where every stand
// has a steady state, any other where its stand's margin is >= 0 or the speed has no steady
// state (that speed is the steady_state limit's to refuse).
bool permits(const std::vector<SteadyFigures>& figures, const SpeedCheck& check) {
    if (check.kind == SpeedLimitKind::steady_state) return all_ok(figures);
    if (!all_ok(figures)) return true;
    return margin(figures[static_cast<std::size_t>(check.stand)], check) >= 0.0;
}

}  // namespace speed_window_detail

SpeedLimitResult speed_window(const std::vector<SpeedCheck>& given, const SteadyAtSpeed& at,
                              double operating_speed, const std::optional<ChatterLimit>& chatter,
                              const CriticalSpeedOptions& options, const Control& control) {
    using namespace speed_window_detail;
    SpeedLimitResult out;
    out.operating_speed = operating_speed;
    constexpr double tolerance = 1e-9;

    // the grid of the critical-speed search, its last point the range's end
    std::vector<double> grid;
    for (int k = 0;; ++k) {
        const double v = options.speed_min + k * options.speed_step;
        if (v >= options.speed_max * (1.0 - 1e-12)) break;
        grid.push_back(v);
    }
    grid.push_back(options.speed_max);
    std::vector<std::vector<SteadyFigures>> figures(grid.size());
    parallel_for(static_cast<int>(grid.size()), control, [&](int k) {
        figures[static_cast<std::size_t>(k)] = at(grid[static_cast<std::size_t>(k)]);
    });
    if (control.should_stop()) {
        out.status = SpeedLimitStatus::cancelled;
        return out;
    }
    const std::vector<SteadyFigures> operating = at(operating_speed);
    const bool operating_ok = all_ok(operating);

    std::vector<SpeedCheck> checks;
    checks.push_back({SpeedLimitKind::steady_state, -1, 0.0});
    checks.insert(checks.end(), given.begin(), given.end());

    // each limit's permitted speeds
    std::vector<std::vector<Interval>> permitted;
    for (const SpeedCheck& check : checks) {
        std::vector<bool> on_grid(grid.size());
        for (std::size_t k = 0; k < grid.size(); ++k) on_grid[k] = permits(figures[k], check);
        permitted.push_back(permitted_intervals(
            grid, on_grid, [&](double v) { return permits(at(v), check); }, tolerance));
    }
    // the chatter limit: every speed up to its speed
    if (chatter) {
        checks.push_back({SpeedLimitKind::chatter, chatter->stand, chatter->speed});
        permitted.push_back(chatter->speed >= options.speed_min
                                ? std::vector<Interval>{{options.speed_min, chatter->speed}}
                                : std::vector<Interval>{});
    }

    std::vector<Interval> all = permitted.front();
    for (std::size_t k = 1; k < permitted.size(); ++k) all = intersect(all, permitted[k]);
    const Interval* window = nearest(all, out.operating_speed);
    if (window != nullptr) {
        out.status = SpeedLimitStatus::ok;
        out.window_min = window->first;
        out.window_max = window->second;
        out.advised_speed = window->second;
        out.operating_permitted =
            out.operating_speed >= window->first && out.operating_speed <= window->second;
    }

    // each limit's own ends around the window (around the operating speed without one)
    const double reference =
        window != nullptr ? 0.5 * (window->first + window->second) : out.operating_speed;
    for (std::size_t k = 0; k < checks.size(); ++k) {
        const SpeedCheck& check = checks[k];
        LimitAnswer answer;
        answer.kind = check.kind;
        answer.stand = check.stand;
        answer.limit = check.limit;
        if (check.kind == SpeedLimitKind::chatter) {
            answer.at_operating = out.operating_speed;
            answer.utilisation = check.limit > 0.0 ? out.operating_speed / check.limit
                                                   : std::numeric_limits<double>::infinity();
            answer.met_at_operating = out.operating_speed <= check.limit;
        } else if (check.kind == SpeedLimitKind::steady_state) {
            answer.at_operating = operating_ok ? 1.0 : 0.0;
            answer.utilisation = std::nan("");
            answer.met_at_operating = operating_ok;
        } else if (!operating_ok) {
            answer.utilisation = std::nan("");
        } else {
            const SteadyFigures& f = operating[static_cast<std::size_t>(check.stand)];
            answer.met_at_operating = margin(f, check) >= 0.0;
            answer.at_operating = figure(f, check.kind);
            answer.utilisation = check.kind == SpeedLimitKind::skid
                                     ? check.limit / answer.at_operating
                                     : answer.at_operating / check.limit;
        }
        if (const Interval* own = nearest(permitted[k], reference)) {
            if (own->first > options.speed_min) answer.lower_speed = own->first;
            if (own->second < options.speed_max) answer.upper_speed = own->second;
        }
        if (window != nullptr) {
            if (answer.lower_speed && *answer.lower_speed == out.window_min && !out.binding_min) {
                out.binding_min = check.kind;
                out.binding_min_stand = check.stand;
            }
            if (answer.upper_speed && *answer.upper_speed == out.window_max && !out.binding_max) {
                out.binding_max = check.kind;
                out.binding_max_stand = check.stand;
            }
        }
        out.limits.push_back(answer);
    }
    return out;
}

SpeedLimitResult speed_limit(const Scenario& s, const PlantLimits& limits,
                             const CriticalSpeedOptions& options, const Control& control) {
    std::vector<SpeedCheck> checks;
    if (limits.max_force) checks.push_back({SpeedLimitKind::force, 0, *limits.max_force});
    if (limits.max_torque) checks.push_back({SpeedLimitKind::torque, 0, *limits.max_torque});
    if (limits.max_power) checks.push_back({SpeedLimitKind::power, 0, *limits.max_power});
    if (limits.min_forward_slip)
        checks.push_back({SpeedLimitKind::skid, 0, *limits.min_forward_slip});

    // the chatter limit: every speed up to (V_c - z sigma)(1 - margin)
    CriticalSpeedResult critical;
    std::optional<ChatterLimit> chatter;
    if (limits.chatter) {
        CriticalSpeedOptions search = options;
        search.stop_at_crossing = true;
        critical = critical_speed(s, search, control);
        if (critical.status == CriticalSpeedStatus::cancelled) {
            SpeedLimitResult out;
            out.operating_speed = s.rolls.speed;
            out.status = SpeedLimitStatus::cancelled;
            return out;
        }
        double limit = options.speed_max;  // stable in the range (or no steady state anywhere)
        if (critical.status == CriticalSpeedStatus::found)
            limit = (critical.critical_speed -
                     normal_quantile(limits.confidence) * limits.chatter_sigma) *
                    (1.0 - limits.chatter_margin);
        else if (critical.status == CriticalSpeedStatus::unstable_at_lower_bound) limit = -1.0;
        chatter = ChatterLimit{limit, 0};
    }
    SpeedLimitResult out = speed_window(
        checks, [&s](double v) { return std::vector<SteadyFigures>{steady_figures(s, v)}; },
        s.rolls.speed, chatter, options, control);
    out.chatter = std::move(critical);
    return out;
}

std::optional<double> limit_crossing(const Scenario& s, SpeedLimitKind kind, double limit,
                                     double near, double half_width) {
    using namespace speed_window_detail;
    const SpeedCheck check{kind, 0, limit};
    const auto g = [&](double v) {
        const SteadyFigures f = steady_figures(s, v);
        return f.ok ? margin(f, check) : std::nan("");
    };
    const double a = std::max(near - half_width, 1e-3), b = near + half_width;
    const double ga = g(a), gb = g(b);
    if (!std::isfinite(ga) || !std::isfinite(gb) || (ga > 0.0) == (gb > 0.0)) return std::nullopt;
    const RootResult root = brent_root(g, a, b, ga, gb, 1e-9 * near);
    if (!root.converged) return std::nullopt;
    return root.x;
}

void bound_window(SpeedLimitResult& r, double z) {
    if (r.status != SpeedLimitStatus::ok) return;
    double high = r.window_max, low = r.window_min;
    for (const LimitAnswer& a : r.limits) {
        if (a.upper_speed && *a.upper_speed >= r.window_max) {
            const double v = *a.upper_speed - z * a.upper_speed_sd.value_or(0.0);
            if (v < high || (v == high && *a.upper_speed == r.window_max)) {
                high = v;
                r.binding_max = a.kind;
                r.binding_max_stand = a.stand;
            }
        }
        if (a.lower_speed && *a.lower_speed <= r.window_min) {
            const double v = *a.lower_speed + z * a.lower_speed_sd.value_or(0.0);
            if (v > low || (v == low && *a.lower_speed == r.window_min)) {
                low = v;
                r.binding_min = a.kind;
                r.binding_min_stand = a.stand;
            }
        }
    }
    if (low > high) {
        r.status = SpeedLimitStatus::no_window;
        r.operating_permitted = false;
        return;
    }
    r.window_min = low;
    r.window_max = high;
    r.advised_speed = high;
    r.operating_permitted = r.operating_speed >= low && r.operating_speed <= high;
}

}  // namespace rollgap::core
