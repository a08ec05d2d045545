// reproduce_paper: regenerates the paper's Figs. 8-15 (Wang et al., Tribology International 67
// (2013) 174-181) with the rollgap core, for both inlet film models (paper, eulerian), as CSV
// files and SVG plots, and writes docs/paper-reproduction.md: per figure the curve the model
// gives, the direction the paper claims, whether they agree and, where they do not, the
// mechanism (from the linearisation of the coupled model, see tools/diagnostics.h).
//
//   reproduce_paper [--out DIR] [--doc FILE] [--threads N]
//
// Defaults: --out docs/paper-reproduction, --doc docs/paper-reproduction.md, a pool of as many
// threads as the CPUs the process may use. Deterministic: every analysis is a pure function of its
// scenario and the sweeps put each result in its own slot, so only the runtime figures change from
// run to run. Nothing here tunes the model: every scenario is docs/model.md §8's default with the
// one field the figure varies (and the stated diagnostics variants, which are labelled as such).

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/parallel_for.h"
#include "service/worker_pool.h"
#include "tools/reproduce_paper/markdown.h"
#include "tools/reproduce_paper/results.h"

using namespace rollgap::tools::paper;
namespace core = rollgap::core;
namespace tools = rollgap::tools;

int main(int argc, char** argv) {
    fs::path out_dir = "docs/paper-reproduction";
    fs::path doc = "docs/paper-reproduction.md";
    int threads = 0;  // 0: the CPUs the process may use (service/cpu_quota.h)
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "reproduce_paper: %s needs a value\n", arg.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (arg == "--out") {
            out_dir = value();
        } else if (arg == "--doc") {
            doc = value();
        } else if (arg == "--threads") {
            threads = std::max(1, std::atoi(value().c_str()));
        } else if (arg == "--help" || arg == "-h") {
            std::printf(
                "usage: reproduce_paper [--out DIR] [--doc FILE] [--threads N]\n"
                "Regenerates the paper's Figs. 8-15 (CSV + SVG in DIR, default docs/paper-reproduction)\n"
                "and writes the comparison FILE (default docs/paper-reproduction.md). Progress on stderr.\n");
            return 0;
        } else {
            std::fprintf(stderr, "reproduce_paper: unknown argument %s (try --help)\n",
                         arg.c_str());
            return 2;
        }
    }
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    if (!doc.parent_path().empty()) fs::create_directories(doc.parent_path(), ec);
    Output out;
    out.dir = out_dir;
    out.doc = doc;
    {
        const fs::path base = doc.parent_path().empty() ? fs::path(".") : doc.parent_path();
        out.link = fs::relative(fs::absolute(out_dir), fs::absolute(base), ec).generic_string();
        if (ec || out.link.empty()) out.link = fs::absolute(out_dir).generic_string();
    }

    const auto t0 = Clock::now();
    Results R;
    // One pool for every parallel loop of the run, as in the service.
    const auto pool = rollgap::service::local_pool(static_cast<std::size_t>(threads));
    core::Control compute;
    compute.executor = pool.get();
    threads = pool->concurrency();
    R.threads = threads;
    R.figures = sweep_figures();
    log("threads: " + std::to_string(threads) + "; output: " + out_dir.string() + ", " +
        doc.string());

    // Figs. 8-12
    for (const SweepFigure& fig : R.figures) {
        std::array<SweepRun, 2> runs;
        for (std::size_t k = 0; k < 2; ++k) {
            runs[k] = run_sweep(fig, film_models[k], compute);
            log("Fig. " + std::to_string(fig.number) + " (" + film_name(film_models[k]) +
                " film): " + std::to_string(fig.xs.size()) + " critical speeds, " +
                std::to_string(runs[k].found) + " found, " + fmt(runs[k].seconds, 1) + " s");
        }
        R.sweeps.push_back(std::move(runs));
    }
    // Diagnostic: Figs. 9, 10, 12 with a fixed friction coefficient
    for (const SweepFigure& fig : R.figures) {
        if (fig.number != 9 && fig.number != 10 && fig.number != 12) continue;
        SweepFigure fixed = fig;
        const double mu = R.coulomb_mu;
        fixed.apply = [apply = fig.apply, mu](Scenario& s, double x) {
            apply(s, x);
            s.friction.model = core::FrictionModel::coulomb;
            s.friction.coulomb_coefficient = mu;
        };
        R.coulomb[fig.number] = run_sweep(fixed, InletFilmModel::paper, compute);
        log("Fig. " + std::to_string(fig.number) + " diagnostic (Coulomb μ = " + fmt(mu, 2) +
            "): " + fmt(R.coulomb[fig.number].seconds, 1) + " s");
    }
    // Fig. 13
    for (std::size_t k = 0; k < 2; ++k) {
        R.amplitude[k] = run_amplitude(film_models[k], compute);
        log(std::string("Fig. 13 (") + film_name(film_models[k]) +
            " film): " + std::to_string(R.amplitude[k].speeds.size()) + " amplitude runs, " +
            fmt(R.amplitude[k].seconds, 1) + " s");
    }
    // Figs. 14-15
    for (std::size_t k = 0; k < 2; ++k) {
        R.cycles[k] = run_cycles(film_models[k], compute);
        log(std::string("Figs. 14-15 (") + film_name(film_models[k]) +
            " film): " + fmt(R.cycles[k].seconds, 1) + " s");
    }
    // The boundary-friction variant: Figs. 8-15 (paper film) with m_a < 1
    R.friction.push_back(paper_friction_reference(R.sweeps, R.amplitude[0], R.cycles[0], compute));
    for (double m_a : boundary_asperity_factors) {
        R.friction.push_back(run_friction_variant(R.figures, m_a, compute));
        log("boundary-friction variant m_a = " + fmt(m_a, 1) +
            " (Figs. 8-15, paper film): " + fmt(R.friction.back().seconds, 1) + " s");
    }
    // Mechanism studies
    {
        const auto t1 = Clock::now();
        const std::vector<Variant> variants = {
            {"defaults: Rayleigh ζ = 0.04 at 100 and 400 Hz, entry span L_b = 5 m, λ_L = 0.05",
             [](Scenario&) {}},
            {"Rayleigh ζ = 0.02", [](Scenario& s) { s.structure.rayleigh_damping_ratio = 0.02; }},
            {"Rayleigh ζ = 0.08", [](Scenario& s) { s.structure.rayleigh_damping_ratio = 0.08; }},
            {"no Rayleigh damping (only c1, c2, as in the paper)",
             [](Scenario& s) { s.structure.rayleigh = false; }},
            {"entry span L_b = 2.5 m", [](Scenario& s) { s.tensions.back.span_length = 2.5; }},
            {"entry span L_b = 10 m", [](Scenario& s) { s.tensions.back.span_length = 10.0; }},
            {"entry span L_b = 20 m", [](Scenario& s) { s.tensions.back.span_length = 20.0; }},
            {"constant back tension (no span state)",
             [](Scenario& s) { s.tensions.back.mode = core::TensionMode::constant; }},
            {"limiting shear λ_L = 0.03",
             [](Scenario& s) { s.lubricant.limiting_shear_coefficient = 0.03; }},
            {"limiting shear λ_L = 0.08",
             [](Scenario& s) { s.lubricant.limiting_shear_coefficient = 0.08; }},
        };
        R.variants = run_variants(variants, compute);
        R.coulomb_mus = {0.03, 0.05, 0.07, 0.10, 0.13, 0.16};
        std::vector<Variant> coulomb;
        for (double mu : R.coulomb_mus) {
            coulomb.push_back({"Coulomb μ = " + fmt(mu, 2), [mu](Scenario& s) {
                                   s.friction.model = core::FrictionModel::coulomb;
                                   s.friction.coulomb_coefficient = mu;
                               }});
        }
        R.coulomb_variants = run_variants(coulomb, compute);
        R.coulomb_diag.resize(R.coulomb_mus.size());
        core::parallel_for(static_cast<int>(R.coulomb_mus.size()), compute, [&](int i) {
            Scenario s;
            s.friction.model = core::FrictionModel::coulomb;
            s.friction.coulomb_coefficient = R.coulomb_mus[static_cast<std::size_t>(i)];
            s.rolls.speed = 15.0;
            R.coulomb_diag[static_cast<std::size_t>(i)] = tools::diagnose(s, 104.0);
        });
        std::vector<double> speeds = {5.0, 10.0, 15.0, 25.0, 30.0};
        const auto& vc = R.variants.front().result;
        if (vc.status == CriticalSpeedStatus::found) speeds.push_back(vc.critical_speed);
        std::sort(speeds.begin(), speeds.end());
        R.defaults_gap_mode = diagnose_over_speed(
            InletFilmModel::paper, speeds,
            vc.status == CriticalSpeedStatus::found ? vc.unstable_mode.frequency_Hz : 104.0, {},
            compute);
        const std::vector<double> high_speeds = {2.0, 5.0, 10.0, 15.0, 19.0, 25.0, 30.0};
        R.high_mode_eulerian =
            diagnose_over_speed(InletFilmModel::eulerian, high_speeds, -1.0, {}, compute);
        R.high_mode_paper.film = InletFilmModel::paper;
        R.high_mode_paper.rows.resize(high_speeds.size());
        core::parallel_for(static_cast<int>(high_speeds.size()), compute, [&](int i) {
            Scenario s;
            s.rolls.speed = high_speeds[static_cast<std::size_t>(i)];
            R.high_mode_paper.rows[static_cast<std::size_t>(i)] = tools::diagnose(
                s, R.high_mode_eulerian.rows[static_cast<std::size_t>(i)].frequency_Hz);
        });
        R.map = stability_map(compute);
        log("mechanism diagnostics: " + fmt(seconds_since(t1), 1) + " s");
    }

    // Outputs
    for (std::size_t i = 0; i < R.figures.size(); ++i) {
        for (std::size_t k = 0; k < 2; ++k) {
            write_sweep_csv(out, R.figures[i], R.sweeps[i][k]);
            const auto fixed = R.coulomb.find(R.figures[i].number);
            plot_sweep(out, R.figures[i], R.sweeps[i][k], R.sweeps[i][0],
                       k == 0 && fixed != R.coulomb.end() ? &fixed->second : nullptr, R.coulomb_mu);
        }
    }
    for (const auto& [number, run] : R.coulomb) {
        for (const SweepFigure& fig : R.figures) {
            if (fig.number != number) continue;
            Csv csv({fig.x_column, "status", "critical_speed_m_s", "mode_frequency_Hz"});
            for (const auto& p : run.points) {
                csv.add({csv_number(p.x), core::to_string(p.result.status),
                         csv_number(p.result.status == CriticalSpeedStatus::found
                                        ? p.result.critical_speed
                                        : no_value),
                         csv_number(p.result.status == CriticalSpeedStatus::found
                                        ? p.result.unstable_mode.frequency_Hz
                                        : no_value)});
            }
            out.csv(fig.id + "_diagnostic_coulomb_mu" + fmt(R.coulomb_mu, 2) + ".csv", csv);
        }
    }
    {
        Csv csv({"speed_m_s", "mode_frequency_Hz", "mean_friction_coefficient", "film_ratio_min",
                 "film_ratio_max", "contact_ratio_max", "inlet_film_um", "strip_stiffness_GN_m",
                 "gap_mass_t", "growth_rate_per_s", "growth_constant_tension_per_s",
                 "growth_frozen_film_per_s", "direct_damping_MN_s_m", "loop_damping_MN_s_m",
                 "film_damping_MN_s_m", "dP_dsb_m2", "du1_dg_per_s", "tension_pole_per_s"});
        for (const auto& d : R.defaults_gap_mode.rows) {
            csv.add({csv_number(d.speed), csv_number(d.frequency_Hz), csv_number(d.mean_friction),
                     csv_number(d.film_ratio_min), csv_number(d.film_ratio_max),
                     csv_number(d.contact_ratio_max), csv_number(d.inlet_film * 1e6),
                     csv_number(d.strip_stiffness * 1e-9), csv_number(d.gap_mass * 1e-3),
                     csv_number(d.growth_rate), csv_number(d.growth_constant_tension),
                     csv_number(d.growth_frozen_film), csv_number(d.direct_damping * 1e-6),
                     csv_number(d.loop_damping * 1e-6), csv_number(d.film_damping * 1e-6),
                     csv_number(d.dP_dback), csv_number(d.du1_dgap), csv_number(d.tension_pole)});
        }
        out.csv("mechanism_gap_mode_over_speed.csv", csv);
        Csv variants({"variant", "status", "critical_speed_m_s", "mode_frequency_Hz"});
        for (const auto* list : {&R.variants, &R.coulomb_variants}) {
            for (const auto& v : *list) {
                variants.add({v.label, core::to_string(v.result.status),
                              csv_number(v.result.status == CriticalSpeedStatus::found
                                             ? v.result.critical_speed
                                             : no_value),
                              csv_number(v.result.status == CriticalSpeedStatus::found
                                             ? v.result.unstable_mode.frequency_Hz
                                             : no_value)});
            }
        }
        out.csv("mechanism_variants.csv", variants);
    }
    for (std::size_t k = 0; k < 2; ++k) write_amplitude_outputs(out, R.amplitude[k]);
    for (std::size_t k = 0; k < 2; ++k) write_cycle_outputs(out, R.cycles[k]);
    write_stability_map(out, R.map);
    write_friction_variant_outputs(out, R.figures, R.friction);

    R.seconds = seconds_since(t0);
    const std::string markdown = write_markdown(R, out);
    {
        std::ofstream file(doc, std::ios::binary);
        file << markdown;
        if (!file) {
            log("cannot write " + doc.string());
            out.ok = false;
        }
    }
    log("done in " + fmt(R.seconds, 1) + " s: " + std::to_string(out.files.size()) + " files in " +
        out_dir.string() + ", " + doc.string());
    return out.ok ? 0 : 1;
}
