#include "service/analyses/table.h"

#include <algorithm>
#include <array>
#include <vector>

#include "api/field_errors.h"
#include "api/name_suggestion.h"
#include "api/text.h"

#include "service/analyses/amplitude.h"
#include "service/analyses/calibration.h"
#include "service/analyses/evaluation.h"
#include "service/analyses/map.h"
#include "service/analyses/roll_gap.h"
#include "service/analyses/stability.h"
#include "service/analyses/sweep.h"
#include "service/analyses/tension_cycle.h"

namespace rollgap::service {
namespace {

constexpr std::array table{
    Analysis{"roll_gap",
             "steady roll-bite pressure, friction and film distributions (docs/model.md §7.1)",
             &prepare_roll_gap},
    Analysis{"tension_cycle",
             "distributions at phases of a sinusoidal back-tension cycle (docs/model.md §7.2)",
             &prepare_tension_cycle},
    Analysis{
        "stability",
        "eigenvalues and modes at the scenario's speed, critical chatter speed (docs/model.md §7.3)",
        &prepare_stability},
    Analysis{"amplitude",
             "vibration amplitude under a back-tension excitation, per speed (docs/model.md §7.4)",
             &prepare_amplitude},
    Analysis{
        "sweep",
        "critical speed or amplitude over the values of one scenario field (docs/model.md §7.5)",
        &prepare_sweep},
    Analysis{"map",
             "critical speed, frequency and chatter type over a grid of two scenario fields "
             "(docs/model.md, \"Stability maps\")",
             &prepare_map},
    Analysis{"evaluate",
             "roll gap, stability, critical speed and amplitude of the scenario at once",
             &prepare_evaluation},
    Analysis{
        "calibrate",
        "fit scenario fields to plant observations, weighted least squares (docs/model.md §11)",
        &prepare_calibration},
};

}  // namespace

std::span<const Analysis> analyses() { return table; }

const Analysis* find_analysis(std::span<const Analysis> offered, std::string_view name) {
    const auto row = std::find_if(offered.begin(), offered.end(), [name](const Analysis& analysis) {
        return analysis.name == name;
    });
    return row == offered.end() ? nullptr : &*row;
}

api::Problem unknown_analysis_problem(std::span<const Analysis> offered, std::string_view name) {
    std::vector<std::string_view> names;
    for (const Analysis& row : offered) names.push_back(row.name);
    return api::make_problem(api::ProblemCode::unknown_analysis,
                             api::concat("no analysis named ", api::quoted_for_message(name)),
                             {{"/analysis",
                               api::concat("unknown analysis ", api::quoted_for_message(name),
                                           api::did_you_mean(name, names)),
                               api::choices_text(names), std::nullopt}});
}

}  // namespace rollgap::service
