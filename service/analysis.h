#pragma once
// What an analysis is to the facade: a name and a function that reads its options and returns
// the computation to run. Reading is separate from running so that every violation of the
// scenario and of the options is reported together, before any physics runs, and so that a
// server can queue the computation with a deadline.

#include <concepts>
#include <functional>
#include <string>
#include <string_view>
#include <utility>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "core/control.h"
#include "core/scenario.h"

namespace rollgap::service {

// Thrown by a run that core reports as cancelled (its Control said stop): the facade turns it
// into the problem `cancelled`. A result with a "cancelled" status is never returned.
struct AnalysisCancelled {};

// For runs: after a core call that may have stopped early, so that a partly computed result
// (a sweep whose last points say "cancelled") is never returned as if it were complete.
inline void throw_if_cancelled(const core::Control& control) {
    if (control.should_stop()) throw AnalysisCancelled{};
}

// The computation of a prepared analysis: the "result" member from the caller's Control
// (cancellation, progress). A computation that cannot be stopped may ignore the Control and be
// written as a function of nothing.
class AnalysisRun {
public:
    AnalysisRun() = default;

    template <class Run>
    requires std::invocable<Run&, const core::Control&> AnalysisRun(Run run)
        : run_(std::move(run)) {}  // NOLINT(google-explicit-constructor)

    template <class Run>
    requires(!std::invocable<Run&, const core::Control&> && std::invocable<Run&>)
        AnalysisRun(Run run)  // NOLINT(google-explicit-constructor)
        : run_([run = std::move(run)](const core::Control&) mutable {
              return nlohmann::json(run());
          }) {}

    nlohmann::json operator()(const core::Control& control = {}) const { return run_(control); }
    explicit operator bool() const { return static_cast<bool>(run_); }

private:
    std::function<nlohmann::json(const core::Control&)> run_;
};

struct PreparedAnalysis {
    nlohmann::json resolved_options;  // the options as applied, echoed with the result
    AnalysisRun run;                  // computes the "result" member; may take a while
};

// Reads `options` strictly (violations under `options_pointer`) and captures what `run` needs.
// Must not compute. `errors` holds the scenario's violations when prepare is called, so the
// scenario is valid iff `errors` is empty on entry; rules that combine the options with the
// scenario run only then.
using PrepareAnalysis = PreparedAnalysis (*)(const core::Scenario& scenario,
                                             const nlohmann::json& options,
                                             const std::string& options_pointer,
                                             api::FieldErrors& errors);

struct Analysis {
    std::string_view name;     // the request's "analysis"
    std::string_view summary;  // one line for --help and the documentation
    PrepareAnalysis prepare;
};

}  // namespace rollgap::service
