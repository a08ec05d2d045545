#include "api/request_json.h"

#include <array>
#include <string_view>

namespace rollgap::api {

AnalysisRequest analysis_request_from_json(const nlohmann::json& request, FieldErrors& errors) {
    AnalysisRequest parsed;
    if (!require_object(request, "", errors)) return parsed;
    static constexpr std::array<std::string_view, 3> known{"analysis", "scenario", "options"};
    reject_unknown_fields(request, "", known, errors);

    if (const auto analysis = request.find("analysis"); analysis == request.end()) {
        errors.add({"/analysis", "required: the name of the analysis to run, e.g. \"roll_gap\"",
                    std::nullopt, std::nullopt});
    } else if (auto name = read_string(*analysis, "/analysis", errors)) {
        parsed.analysis = std::move(*name);
    }
    // null is treated as absent: many clients serialise a missing optional member as null.
    if (const auto scenario = request.find("scenario");
        scenario != request.end() && !scenario->is_null()) {
        parsed.scenario_patch = *scenario;
    }
    if (const auto options = request.find("options");
        options != request.end() && !options->is_null()) {
        parsed.options = *options;
    }
    return parsed;
}

}  // namespace rollgap::api
