// Timing of rollgap's analyses for the default scenario: the roll-bite solve (docs/model.md §4),
// the linearisation alone (§6.1), the critical speed (§7.3), the amplitude (§7.4) and a
// critical-speed sweep (§7.5).
//
// Output, one figure per line on stdout, in a stable format that scripts can parse:
//     <bench>.<figure>: <value> <unit>
// e.g. "roll_gap.distributions.median: 123.456 us". Diagnostics go to stderr.
//
// Usage: bench_model [--filter SUBSTRING] [--min-time SECONDS] [--reps N] [--list]
//
// To add a bench (critical speed, amplitude, sweep, ...): write a function
// `int bench_xxx(const Config&)` that calls time_it() and print_timing(), and add it to
// kBenches at the bottom. A bench returns non-zero when the thing it timed did not succeed
// (timing a failure path would give meaningless figures).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "core/amplitude.h"
#include "core/control.h"
#include "core/coupled_model.h"
#include "core/mill/mill.h"
#include "core/mill/mill_critical_speed.h"
#include "core/mill/mill_delay.h"
#include "core/mill/mill_model.h"
#include "core/mill/mill_regenerative.h"
#include "core/mill/mill_stability.h"
#include "core/mill/mill_time.h"
#include "service/worker_pool.h"
#include "core/roll_bite.h"
#include "core/scenario.h"
#include "core/stability.h"
#include "core/sweep.h"

namespace {

using Clock = std::chrono::steady_clock;

struct Config {
    double min_time_s = 1.0;   // measure at least this long ...
    long min_reps = 2000;      // ... and at least this many repetitions,
    double max_time_s = 20.0;  // but stop after this long once min_reps_hard are done
    long min_reps_hard = 20;
    double warmup_s = 0.2;  // warm-up: this long or warmup_reps, whichever comes first
    long warmup_reps = 200;
};

struct Timing {
    std::vector<double> us;  // per-call wall time, microseconds, sorted ascending
    double total_s = 0.0;
};

// Keeps the optimiser from discarding the timed work.
volatile double g_sink = 0.0;

// Times `call` repeatedly, one clock reading around each call.
Timing time_it(const Config& cfg, const std::function<double()>& call) {
    const auto warm_start = Clock::now();
    for (long i = 0; i < cfg.warmup_reps; ++i) {
        g_sink = g_sink + call();
        if (std::chrono::duration<double>(Clock::now() - warm_start).count() >= cfg.warmup_s) break;
    }

    Timing t;
    t.us.reserve(static_cast<std::size_t>(cfg.min_reps));
    const auto start = Clock::now();
    for (;;) {
        const auto t0 = Clock::now();
        g_sink = g_sink + call();
        const auto t1 = Clock::now();
        t.us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
        const double elapsed = std::chrono::duration<double>(t1 - start).count();
        const auto n = static_cast<long>(t.us.size());
        const bool enough = n >= cfg.min_reps && elapsed >= cfg.min_time_s;
        const bool out_of_time = elapsed >= cfg.max_time_s && n >= cfg.min_reps_hard;
        if (enough || out_of_time) {
            t.total_s = elapsed;
            break;
        }
    }
    std::sort(t.us.begin(), t.us.end());
    return t;
}

// Percentile of sorted data, linear interpolation between order statistics (q in [0, 1]).
double percentile(const std::vector<double>& sorted, double q) {
    if (sorted.empty()) return std::nan("");
    const double pos = q * static_cast<double>(sorted.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(pos));
    const auto hi = std::min(lo + 1, sorted.size() - 1);
    const double frac = pos - static_cast<double>(lo);
    return sorted[lo] + frac * (sorted[hi] - sorted[lo]);
}

void print_figure(const std::string& name, double value, const char* unit) {
    std::printf("%s: %.6g %s\n", name.c_str(), value, unit);
}

void print_count(const std::string& name, long value) {
    std::printf("%s: %ld count\n", name.c_str(), value);
}

void print_timing(const std::string& name, const Timing& t) {
    print_figure(name + ".median", percentile(t.us, 0.50), "us");
    print_figure(name + ".p10", percentile(t.us, 0.10), "us");
    print_figure(name + ".p90", percentile(t.us, 0.90), "us");
    print_count(name + ".samples", static_cast<long>(t.us.size()));
    std::fflush(stdout);
}

// ---- benches --------------------------------------------------------------------------------

// solve_roll_bite(scenario, steady_bite_state(scenario)) for the default scenario, with and
// without the distributions p(x), tau(x), ... (the state is computed inside the timed call).
int bench_roll_gap(const Config& cfg) {
    const rollgap::core::Scenario scenario{};

    // One untimed solve to check that we time the real path, not an early failure.
    const auto check =
        rollgap::core::solve_roll_bite(scenario, rollgap::core::steady_bite_state(scenario));
    if (check.status != rollgap::core::BiteStatus::ok) {
        std::fprintf(stderr, "roll_gap: default scenario did not solve: %s (%s)\n",
                     rollgap::core::to_string(check.status), check.message);
        return 1;
    }
    print_figure("roll_gap.force", check.force, "N");
    print_count("roll_gap.distribution_points", static_cast<long>(check.distribution.size()));

    for (const bool distributions : {true, false}) {
        rollgap::core::BiteOptions options;
        options.distributions = distributions;
        const Timing t = time_it(cfg, [&] {
            const auto r = rollgap::core::solve_roll_bite(
                scenario, rollgap::core::steady_bite_state(scenario), options);
            return r.force;
        });
        print_timing(distributions ? "roll_gap.distributions" : "roll_gap.no_distributions", t);
    }
    return 0;
}

// The Jacobian of the default coupled model at z0 (19 m/s), as each stability point takes it: the
// model's jacobian() (assembled from the bite linearisation J_b, docs/model.md §6.1) and the
// central differences of the whole right-hand side it replaced (finite_difference_jacobian).
// Each call builds a fresh model, whose bite memo holds only the reference bite, as analyse()
// does; `model_only` times that construction alone. `bite_solves` counts solve_roll_bite calls
// per linearisation (the reference state's own three, steady bite and k4, are not included).
int bench_linearisation(const Config& cfg) {
    namespace core = rollgap::core;
    const core::Scenario s = core::dynamics_scenario(core::Scenario{});
    const core::ReferenceState ref = core::reference_state(s, false);
    if (ref.status != core::BiteStatus::ok) {
        std::fprintf(stderr, "linearisation: no steady bite (%s)\n", ref.message);
        return 1;
    }
    const Timing model_only = time_it(cfg, [&] {
        const core::CoupledModel model(s, ref);
        return model.equilibrium()(core::CoupledModel::film_index);
    });
    print_timing("linearisation.model_only", model_only);
    for (const bool assembled : {true, false}) {
        const std::string name = assembled ? "linearisation.assembled" : "linearisation.fd";
        const auto linearise = [&](const core::CoupledModel& model) {
            const Eigen::VectorXd z0 = model.equilibrium();
            return assembled ? model.jacobian(z0, 0.0)
                             : core::finite_difference_jacobian(model, z0, 0.0);
        };
        const core::CoupledModel counted(s, ref);
        const core::Linearisation check = linearise(counted);
        if (check.status != core::DynamicsStatus::ok) {
            std::fprintf(stderr, "%s: %s\n", name.c_str(), core::to_string(check.status));
            return 1;
        }
        print_count(name + ".bite_solves", counted.bite_solves());
        const Timing t = time_it(cfg, [&] {
            const core::CoupledModel model(s, ref);
            return linearise(model).jacobian(6 + 2, 2);
        });
        print_timing(name, t);
    }
    // J_b alone at the reference bite, the columns a default stand moves (y2, gap rate, h0, back
    // tension), by each method (docs/model.md §6.1)
    const core::CoupledModel model(s, ref);
    const Eigen::VectorXd z0 = model.equilibrium();
    const core::BiteState at = model.bite_state(0.0, z0.data());
    const unsigned columns = core::bite_column(core::BiteInput::exit_thickness) |
                             core::bite_column(core::BiteInput::gap_rate) |
                             core::bite_column(core::BiteInput::inlet_film) |
                             core::bite_column(core::BiteInput::back_tension);
    for (const bool sensitivities : {true, false}) {
        const std::string name =
            sensitivities ? "bite_jacobian.sensitivities" : "bite_jacobian.differences";
        const auto jb = [&] {
            return sensitivities ? core::bite_jacobian(s, at, ref.bite, columns)
                                 : core::bite_jacobian_differences(s, at, ref.bite, columns);
        };
        if (jb().status != core::BiteStatus::ok) {
            std::fprintf(stderr, "%s: %s\n", name.c_str(), jb().message);
            return 1;
        }
        print_timing(name, time_it(cfg, [&] { return jb().derivative(0, 1); }));
    }
    return 0;
}

// The expensive analyses repeat a few times, not thousands.
Config heavy(const Config& cfg, long reps) {
    Config c = cfg;
    c.min_reps = std::min(cfg.min_reps, reps);
    c.min_reps_hard = std::min(c.min_reps, 3L);
    c.warmup_reps = 1;
    return c;
}

// The critical speed of the default scenario over 1-60 m/s, on one thread and on all cores:
// the full scan (detail "full") and the scan that stops at the first crossing ("summary",
// sweeps, maps, calibration; docs/model.md §7.3).
int bench_critical_speed(const Config& cfg) {
    const rollgap::core::Scenario scenario{};
    const auto pool = rollgap::service::local_pool();
    for (const bool summary : {false, true}) {
        const std::string name = summary ? "critical_speed_summary" : "critical_speed";
        for (const int threads : {1, pool->concurrency()}) {
            rollgap::core::CriticalSpeedOptions options;
            options.stop_at_crossing = summary;
            rollgap::core::Control control;
            control.executor = pool.get();
            control.threads = threads;
            const auto check = rollgap::core::critical_speed(scenario, options, control);
            if (check.status != rollgap::core::CriticalSpeedStatus::found) {
                std::fprintf(stderr, "%s: not found (%s)\n", name.c_str(),
                             rollgap::core::to_string(check.status));
                return 1;
            }
            if (threads == 1) {
                print_figure(name + ".value", check.critical_speed, "m/s");
                print_count(name + ".scanned_speeds", static_cast<long>(check.scan.size()));
            }
            const Timing t = time_it(heavy(cfg, 20), [&] {
                return rollgap::core::critical_speed(scenario, options, control).critical_speed;
            });
            print_timing(name + ".threads_" + std::to_string(threads), t);
        }
    }
    return 0;
}

// One second of simulated time of the excited nonlinear model at the default 19 m/s.
int bench_amplitude(const Config& cfg) {
    const rollgap::core::Scenario scenario{};
    rollgap::core::AmplitudeOptions options;
    options.window = 1.0;
    const auto check = rollgap::core::vibration_amplitude(scenario, options);
    if (check.end_status != rollgap::core::DynamicsStatus::ok) {
        std::fprintf(stderr, "amplitude: run ended early (%s)\n", check.message);
        return 1;
    }
    print_figure("amplitude_1s.upper_roll", check.upper_roll * 1e6, "um");
    print_count("amplitude_1s.steps", check.steps);
    print_count("amplitude_1s.rhs_evaluations", check.rhs_evaluations);
    print_count("amplitude_1s.jacobian_evaluations", check.jacobian_evaluations);
    print_count("amplitude_1s.jacobian_rhs_evaluations", check.jacobian_rhs_evaluations);
    const Timing t = time_it(heavy(cfg, 5), [&] {
        return rollgap::core::vibration_amplitude(scenario, options).upper_roll;
    });
    print_timing("amplitude_1s", t);
    return 0;
}

// A 100-point critical-speed sweep over the viscosity (Fig. 8's axis) on all cores.
int bench_sweep(const Config& cfg) {
    std::vector<rollgap::core::Scenario> scenarios(100);
    for (std::size_t i = 0; i < scenarios.size(); ++i) {
        scenarios[i].lubricant.viscosity = 2e-4 + 1.8e-3 * static_cast<double>(i) / 99.0;
    }
    const auto pool = rollgap::service::local_pool();
    rollgap::core::Control control;
    control.executor = pool.get();
    print_count("sweep_100.threads", control.thread_budget());
    const Timing t = time_it(heavy(cfg, 2), [&] {
        // As the sweep analysis runs it: no scans kept, each search to its first crossing.
        const auto results =
            rollgap::core::sweep_critical_speed(scenarios, {}, control, /*keep_scan=*/false);
        return results.front().critical_speed;
    });
    print_timing("sweep_100", t);
    return 0;
}

// The default 5-stand mill (docs/model.md §12) at 15 m/s: the schedule's steady state; the
// stability at one speed (schedule, A0 and B assembled, eigenvalues, M in the modal basis, the
// regenerative margin), and its parts; the frozen critical speed on all cores.
int bench_mill(const Config& cfg) {
    namespace core = rollgap::core;
    const core::Mill mill = core::default_mill();
    const core::MillSteadyState check = core::mill_steady_state(mill);
    if (check.status != core::MillSteadyStatus::ok) {
        std::fprintf(stderr, "mill: no steady state (%s)\n", check.message);
        return 1;
    }
    int solves = 0;
    for (const auto& stand : check.stands) solves += stand.bite_solves;
    print_count("mill_steady.bite_solves", solves);
    print_timing("mill_steady",
                 time_it(cfg, [&] { return core::mill_steady_state(mill).mass_flow; }));

    // 0: the frozen eigenvalues' rightmost real part; 1: and rho; 2: and the nominal count
    const auto stability = [&](int level) {
        const core::MillSteadyState steady = core::mill_steady_state(mill);
        const core::MillModel model(mill, steady);
        const core::MillLinearisation lin = model.linearise(model.equilibrium());
        const core::TransportTransfer transfer = core::transport_transfer(lin);
        if (level == 0) return transfer.frozen_max_real_part;
        const double rho = core::regenerative_margin(transfer).margin;
        if (level == 1) return rho;
        return rho + core::nominal_delay_root_count(transfer, 0.0).count;
    };
    const core::MillSteadyState steady = core::mill_steady_state(mill);
    const core::MillModel model(mill, steady);
    const core::MillLinearisation lin = model.linearise(model.equilibrium());
    const core::TransportTransfer transfer = core::transport_transfer(lin);
    const core::RegenerativeMargin margin = core::regenerative_margin(transfer);
    print_count("mill_stability.states", model.size());
    print_figure("mill_stability.margin", margin.margin, "1");
    print_figure("mill_stability.margin_frequency", margin.frequency_Hz, "Hz");
    print_count("mill_stability.margin_evaluations", margin.evaluations);
    print_timing("mill_stability.linearise", time_it(heavy(cfg, 200), [&] {
                     return model.linearise(model.equilibrium()).jacobian(0, 0);
                 }));
    print_timing("mill_stability.modal_basis", time_it(heavy(cfg, 200), [&] {
                     return core::transport_transfer(lin).frozen_max_real_part;
                 }));
    print_timing("mill_stability.transfer_at", time_it(cfg, [&] {
                     return std::abs(transfer.at({0.0, 650.0})(0, 0));
                 }));
    print_timing("mill_stability.margin", time_it(heavy(cfg, 200), [&] {
                     return core::regenerative_margin(transfer).margin;
                 }));
    print_timing("mill_stability.frozen", time_it(heavy(cfg, 100), [&] { return stability(0); }));
    print_timing("mill_stability.frozen_and_margin",
                 time_it(heavy(cfg, 100), [&] { return stability(1); }));
    const core::DelayRootCount count = core::nominal_delay_root_count(transfer, 0.0);
    print_count("mill_stability.nominal_count", count.count);
    print_count("mill_stability.nominal_count_evaluations", count.evaluations);
    print_timing("mill_stability.nominal_count", time_it(heavy(cfg, 50), [&] {
                     return core::nominal_delay_root_count(transfer, 0.0).winding;
                 }));
    const core::RightmostDelayRoot right = core::rightmost_delay_root(transfer, count);
    print_figure("mill_stability.rightmost_growth_rate", right.root.s.real(), "1/s");
    print_figure("mill_stability.rightmost_frequency", right.root.s.imag() / (2.0 * M_PI), "Hz");
    print_count("mill_stability.rightmost_starts", right.starts);
    print_timing("mill_stability.rightmost", time_it(heavy(cfg, 50), [&] {
                     return core::rightmost_delay_root(transfer, count).root.s.real();
                 }));
    print_timing("mill_stability.frozen_margin_count",
                 time_it(heavy(cfg, 50), [&] { return stability(2); }));
    print_timing("mill_stability.at_speed", time_it(heavy(cfg, 50), [&] {
                     return core::mill_stability_at(mill).margin.margin;
                 }));

    const auto pool = rollgap::service::local_pool();
    core::Control control;
    control.executor = pool.get();

    // the three critical speeds: two stands (the default mill's last two, 5 m span) and five
    const auto print_speeds = [&](const std::string& name, const core::Mill& m, long reps) {
        const core::MillCriticalSpeeds speeds = core::mill_critical_speeds(m, {}, control);
        const std::pair<const char*, const core::MillCrossing*> crossings[] = {
            {"frozen", &speeds.frozen},
            {"delay_independent", &speeds.delay_independent},
            {"nominal_delay", &speeds.nominal_delay},
            {"first_any", &speeds.first_any}};
        for (const auto& [label, c] : crossings) {
            const std::string kind = label;
            print_figure(name + "." + kind + ".speed", c->speed, "m/s");
            print_figure(name + "." + kind + ".frequency", c->frequency_Hz, "Hz");
            print_count(name + "." + kind + ".moving_stand", c->moving_stand + 1);
            print_count(name + "." + kind + ".feeding_stand", c->feeding_stand + 1);
            print_count(name + "." + kind + ".valid", c->validity.valid() ? 1 : 0);
        }
        print_count(name + ".headline", speeds.headline);
        // the whole answer (frozen, delay-independent, first_any and nominal-delay searches with
        // their descriptions) on the pool's threads; issue 19's goal: 5 stands <= 2 s, two
        // stands <= 0.5 s on 2 threads
        print_count(name + ".threads", control.thread_budget());
        print_timing(name, time_it(heavy(cfg, reps), [&] {
                         return core::mill_critical_speeds(m, {}, control).frozen.speed;
                     }));
    };
    core::Mill two = mill;
    two.stands = {mill.stands[3], mill.stands[4]};
    two.thickness = {mill.thickness[3], mill.thickness[4], mill.thickness[5]};
    two.span_length = {mill.span_length[3]};
    two.interstand_tension = {mill.interstand_tension[3]};
    two.entry_tension = mill.interstand_tension[2];
    print_speeds("mill_critical_speeds_2", two, 5);
    print_speeds("mill_critical_speeds_5", mill, 1);

    core::CriticalSpeedOptions options;
    options.stop_at_crossing = true;
    const core::CriticalSpeedResult frozen =
        core::mill_frozen_critical_speed(mill, options, control);
    print_figure("mill_frozen_critical_speed.speed", frozen.critical_speed, "m/s");
    print_count("mill_frozen_critical_speed.threads", control.thread_budget());
    print_timing("mill_frozen_critical_speed", time_it(heavy(cfg, 3), [&] {
                     return core::mill_frozen_critical_speed(mill, options, control).critical_speed;
                 }));
    return 0;
}

// The mill in the time domain (core/mill/mill_time.h): the default mill's last two stands (5 m
// span) at 15 m/s, 1 s from a 0.1 um gap kick on the last stand, outputs every millisecond, the
// thickness transport read off its history.
int bench_mill_time(const Config& cfg) {
    namespace core = rollgap::core;
    const core::Mill d = core::default_mill();
    core::Mill two = d;
    two.stands = {d.stands[3], d.stands[4]};
    two.thickness = {d.thickness[3], d.thickness[4], d.thickness[5]};
    two.span_length = {d.span_length[3]};
    two.interstand_tension = {d.interstand_tension[3]};
    two.entry_tension = d.interstand_tension[2];
    const core::MillSteadyState steady = core::mill_steady_state(two);
    if (steady.status != core::MillSteadyStatus::ok) {
        std::fprintf(stderr, "mill_time: no steady state (%s)\n", steady.message);
        return 1;
    }
    core::MillKick kick;
    kick.stand = 1;
    kick.gap = 1e-7;
    std::vector<double> times;
    for (int i = 1; i <= 1000; ++i) times.push_back(1e-3 * i);
    const core::MillTimeResult run = core::mill_time_domain(two, steady, kick, times);
    if (run.status != core::MillTimeStatus::ok) {
        std::fprintf(stderr, "mill_time: %s (%s)\n", core::to_string(run.status), run.message);
        return 1;
    }
    print_count("mill_time_2.steps", run.steps);
    print_count("mill_time_2.rhs_evaluations", run.rhs_evaluations);
    print_count("mill_time_2.jacobian_evaluations", run.jacobian_evaluations);
    print_timing("mill_time_2", time_it(heavy(cfg, 3), [&] {
                     return core::mill_time_domain(two, steady, kick, times).end_time;
                 }));
    return 0;
}

struct Bench {
    const char* name;
    int (*run)(const Config&);
};

// Register new benches here.
constexpr Bench kBenches[] = {
    {"roll_gap", bench_roll_gap},
    {"linearisation", bench_linearisation},
    {"critical_speed", bench_critical_speed},
    {"amplitude", bench_amplitude},
    {"sweep", bench_sweep},
    {"mill", bench_mill},
    {"mill_time", bench_mill_time},
};

[[noreturn]] void usage(const char* argv0, int code) {
    std::fprintf(code == 0 ? stdout : stderr,
                 "usage: %s [--filter SUBSTRING] [--min-time SECONDS] [--reps N] [--list]\n",
                 argv0);
    std::exit(code);
}

}  // namespace

int main(int argc, char** argv) {
    Config cfg;
    std::string filter;
    bool list = false;
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        const bool has_value = i + 1 < argc;
        if (arg == "--filter" && has_value) {
            filter = argv[++i];
        } else if (arg == "--min-time" && has_value) {
            cfg.min_time_s = std::atof(argv[++i]);
        } else if (arg == "--reps" && has_value) {
            cfg.min_reps = std::atol(argv[++i]);
        } else if (arg == "--list") {
            list = true;
        } else if (arg == "--help" || arg == "-h") {
            usage(argv[0], 0);
        } else {
            usage(argv[0], 2);
        }
    }

    int failures = 0;
    int ran = 0;
    for (const Bench& b : kBenches) {
        if (!filter.empty() && std::string_view(b.name).find(filter) == std::string_view::npos)
            continue;
        if (list) {
            std::printf("%s\n", b.name);
            continue;
        }
        ++ran;
        if (b.run(cfg) != 0) ++failures;
    }
    if (!list && ran == 0) {
        std::fprintf(stderr, "no bench matches filter '%s'\n", filter.c_str());
        return 2;
    }
    return failures == 0 ? 0 : 1;
}
