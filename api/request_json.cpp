#include "api/request_json.h"

#include <algorithm>
#include <array>
#include <string_view>

#include "api/interval.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

constexpr std::size_t max_name_length = 64;

bool name_character(char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' ||
           c == '_' || c == '-';
}

// "base": a name, or the resolved {"name", "version"} form.
void read_base(const nlohmann::json& base, AnalysisRequest& parsed, FieldErrors& errors) {
    if (base.is_string()) {
        const std::string& name = base.get_ref<const std::string&>();
        if (auto error = stored_scenario_name_error(name, "/base")) {
            errors.add(std::move(*error));
        } else {
            parsed.unresolved_base = name;
        }
        return;
    }
    if (!base.is_object()) {
        errors.add(
            {"/base",
             concat("must be the name of a stored scenario (a string), not ", json_type_name(base)),
             std::string(stored_scenario_name_pattern), std::nullopt});
        return;
    }
    parsed.base = read_resolved_base(base, "/base", errors);
}

}  // namespace

std::optional<ScenarioBase> read_resolved_base(const nlohmann::json& base,
                                               const std::string& pointer, FieldErrors& errors) {
    static constexpr std::array<std::string_view, 2> known{"name", "version"};
    reject_unknown_fields(base, pointer, known, errors);
    ScenarioBase resolved;
    bool complete = true;
    const std::string name_at = pointer + "/name";
    if (const auto name = base.find("name"); name == base.end()) {
        errors.add({name_at, "required", std::nullopt, std::nullopt});
        complete = false;
    } else if (auto text = read_string(*name, name_at, errors)) {
        if (auto error = stored_scenario_name_error(*text, name_at)) {
            errors.add(std::move(*error));
            complete = false;
        }
        resolved.name = std::move(*text);
    } else {
        complete = false;
    }
    // Versions count writes from 1; 2^53 - 1 keeps them exact in every JSON client.
    const Interval versions = closed(1.0, 9007199254740991.0);
    const std::string version_at = pointer + "/version";
    if (const auto version = base.find("version"); version == base.end()) {
        errors.add({version_at, "required", std::nullopt, std::nullopt});
        complete = false;
    } else if (auto number = read_integer(*version, version_at, versions, false, errors)) {
        resolved.version = *number;
    } else {
        complete = false;
    }
    if (!complete) return std::nullopt;
    return resolved;
}

bool is_stored_scenario_name(std::string_view name) {
    if (name.empty() || name.size() > max_name_length || name == reserved_scenario_name)
        return false;
    const char first = name.front();
    if (first == '.' || first == '_' || first == '-') return false;
    return std::all_of(name.begin(), name.end(), name_character);
}

std::optional<FieldError> stored_scenario_name_error(std::string_view name,
                                                     const std::string& pointer) {
    if (is_stored_scenario_name(name)) return std::nullopt;
    if (name == reserved_scenario_name) {
        return FieldError{pointer,
                          concat("'", reserved_scenario_name,
                                 "' is reserved for the built-in default scenario "
                                 "(GET /v1/scenarios/default); choose another name"),
                          std::string(stored_scenario_name_pattern), std::nullopt};
    }
    return FieldError{pointer,
                      concat(quoted_for_message(name),
                             " is not a scenario name: 1 to 64 of A-Z a-z 0-9 . _ -, starting "
                             "with a letter or digit"),
                      std::string(stored_scenario_name_pattern), std::nullopt};
}

nlohmann::json scenario_base_json(const ScenarioBase& base) {
    return {{"name", base.name}, {"version", base.version}};
}

AnalysisRequest analysis_request_from_json(const nlohmann::json& request, FieldErrors& errors) {
    AnalysisRequest parsed;
    if (!require_object(request, "", errors)) return parsed;
    static constexpr std::array<std::string_view, 5> known{"analysis", "base", "scenario", "tandem",
                                                           "options"};
    reject_unknown_fields(request, "", known, errors);

    if (const auto analysis = request.find("analysis"); analysis == request.end()) {
        errors.add({"/analysis", "required: the name of the analysis to run, e.g. \"roll_gap\"",
                    std::nullopt, std::nullopt});
    } else if (auto name = read_string(*analysis, "/analysis", errors)) {
        parsed.analysis = std::move(*name);
    }
    // null is treated as absent: many clients serialise a missing optional member as null.
    if (const auto base = request.find("base"); base != request.end() && !base->is_null()) {
        read_base(*base, parsed, errors);
    }
    if (const auto scenario = request.find("scenario");
        scenario != request.end() && !scenario->is_null()) {
        parsed.scenario_patch = *scenario;
    }
    if (const auto tandem = request.find("tandem"); tandem != request.end() && !tandem->is_null()) {
        parsed.tandem_patch = *tandem;
    }
    if (const auto options = request.find("options");
        options != request.end() && !options->is_null()) {
        parsed.options = *options;
    }
    return parsed;
}

}  // namespace rollgap::api
