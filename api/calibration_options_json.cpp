// Reading the calibrate analysis' options (api/calibration_json.h): the fitted fields, the
// observations and their quantities, the solver's limits; the result writer is in
// calibration_json.cpp.
#include "api/calibration_json.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <optional>
#include <string_view>
#include <utility>

#include "api/json_pointer.h"
#include "api/name_suggestion.h"
#include "api/option_table.h"
#include "api/options_reader.h"
#include "api/quantity_json.h"
#include "api/result_table.h"
#include "api/posterior_json.h"
#include "api/scenario_json.h"
#include "api/stability_json.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

constexpr std::array<std::string_view, 5> option_members{"parameters", "observations",
                                                         option_name(OptionId::max_iterations),
                                                         "critical_speed", "joint_prior"};
constexpr std::array<std::string_view, 4> parameter_members{"field", "min", "max", "prior"};
constexpr std::array<std::string_view, 2> prior_members{"value", "standard_uncertainty"};
constexpr std::array<std::string_view, 5> observation_members{"scenario", "quantity", "value",
                                                              "standard_uncertainty", "mode"};
constexpr std::array<std::string_view, 2> mode_members{"index", "near_frequency_Hz"};

const std::vector<std::string_view>& fittable_paths() {
    static const std::vector<std::string_view> paths = [] {
        std::vector<std::string_view> out;
        for (const ScenarioField& field : scenario_fields()) {
            if (field.kind == FieldKind::number) out.push_back(field.path);
        }
        return out;
    }();
    return paths;
}

std::vector<std::string_view> quantity_names() {
    std::vector<std::string_view> names;
    for (const auto& q : calibration_quantities()) names.push_back(q.name);
    return names;
}

// A field's own range as a closed box the fit can touch: an open end moves inside by a
// relative 1e-9 of the range (the asperity factor's (0, 1] has no usable 0).
std::pair<double, double> closed_box(const Interval& range) {
    const double inset = 1e-9 * (range.max - range.min);
    return {range.min_open ? range.min + inset : range.min,
            range.max_open ? range.max - inset : range.max};
}

struct ParameterRead {
    const ScenarioField* field = nullptr;
    core::CalibrationParameter parameter;  // SI; start filled later from the scenario
    nlohmann::json echo;
};

std::optional<ParameterRead> read_parameter(const nlohmann::json& value, const std::string& pointer,
                                            FieldErrors& errors) {
    const OptionsReader reader(value, pointer, parameter_members, errors);
    if (!reader.is_object()) return std::nullopt;
    ParameterRead out;
    out.field = read_fitted_field(reader.find("field"), reader.at("field"), errors);
    if (out.field == nullptr) return std::nullopt;
    const ScenarioField& field = *out.field;
    const auto [box_min, box_max] = closed_box(field.range);
    std::optional<double> min, max;
    if (const auto* v = reader.find("min"))
        min = read_number(*v, reader.at("min"), field.range, field.unit, errors);
    if (const auto* v = reader.find("max"))
        max = read_number(*v, reader.at("max"), field.range, field.unit, errors);
    if ((reader.find("min") != nullptr && !min) || (reader.find("max") != nullptr && !max))
        return std::nullopt;
    out.parameter.lower = min ? to_si(*min, field.unit) : to_si(box_min, field.unit);
    out.parameter.upper = max ? to_si(*max, field.unit) : to_si(box_max, field.unit);
    if (!(out.parameter.lower < out.parameter.upper)) {
        errors.add({reader.at("max"),
                    concat("must be above min (",
                           format_number(from_si(out.parameter.lower, field.unit)), ")"),
                    std::nullopt, std::string(field.unit.code)});
        return std::nullopt;
    }
    out.echo = {{"field", field.path},
                {"min", from_si(out.parameter.lower, field.unit)},
                {"max", from_si(out.parameter.upper, field.unit)},
                {"prior", nullptr}};
    // null, as the answer echoes a parameter without one: no prior (the echo reruns)
    if (const auto* prior = reader.find("prior"); prior != nullptr && !prior->is_null()) {
        const OptionsReader prior_reader(*prior, reader.at("prior"), prior_members, errors);
        if (!prior_reader.is_object()) return std::nullopt;
        bool ok = true;
        for (const std::string_view name : prior_members) {
            if (prior_reader.find(name) == nullptr) {
                errors.add({prior_reader.at(name),
                            concat("required, in the field's unit (", field.unit.code, ")"),
                            std::nullopt, std::string(field.unit.code)});
                ok = false;
            }
        }
        double value_si = 0.0, sigma_si = 0.0;
        ok = prior_reader.number("value", field.unit, field.range, value_si) && ok;
        ok = prior_reader.number("standard_uncertainty", field.unit, open_closed(0.0, 1e300),
                                 sigma_si) &&
             ok;
        if (!ok) return std::nullopt;
        out.parameter.has_prior = true;
        out.parameter.prior_value = value_si;
        out.parameter.prior_uncertainty = sigma_si;
        out.echo["prior"] = {{"value", from_si(value_si, field.unit)},
                             {"standard_uncertainty", from_si(sigma_si, field.unit)}};
    }
    return out;
}

const CalibrationQuantity* find_quantity(std::string_view name) {
    for (const auto& q : calibration_quantities()) {
        if (q.name == name) return &q;
    }
    return nullptr;
}

struct ObservationRead {
    const CalibrationQuantity* quantity = nullptr;
    nlohmann::json patch = nlohmann::json::object();
    std::string patch_pointer;
    double value = 0.0, uncertainty = 0.0;  // SI
    core::ModeChoice mode;
    nlohmann::json echo;
};

std::optional<ObservationRead> read_observation(const nlohmann::json& value,
                                                const std::string& pointer, FieldErrors& errors) {
    const OptionsReader reader(value, pointer, observation_members, errors);
    if (!reader.is_object()) return std::nullopt;
    ObservationRead out;
    bool ok = true;
    if (const auto* q = reader.find("quantity")) {
        const auto names = quantity_names();
        if (const auto name = read_choice(*q, reader.at("quantity"), names, errors)) {
            out.quantity = find_quantity(*name);
        } else {
            ok = false;
        }
    } else {
        errors.add({reader.at("quantity"), "required: what was measured",
                    choices_text(quantity_names()), std::nullopt});
        ok = false;
    }
    const Unit unit = out.quantity != nullptr ? out.quantity->unit : units::one;
    for (const std::string_view name :
         {std::string_view("value"), std::string_view("standard_uncertainty")}) {
        if (reader.find(name) == nullptr) {
            errors.add({reader.at(name), "required, in the quantity's unit", std::nullopt,
                        std::string(unit.code)});
            ok = false;
        }
    }
    // A zero uncertainty would be an infinite weight: the observation would have to be met
    // exactly and the covariance would not exist.
    ok = reader.number("value", unit, closed(-1e300, 1e300), out.value) && ok;
    ok =
        reader.number("standard_uncertainty", unit, open_closed(0.0, 1e300), out.uncertainty) && ok;
    out.patch_pointer = reader.at("scenario");
    // absent or null: the request's scenario as it is
    if (const auto* patch = reader.find("scenario"); patch != nullptr && !patch->is_null()) {
        if (require_object(*patch, out.patch_pointer, errors)) {
            out.patch = *patch;
        } else {
            ok = false;
        }
    }
    const bool modal = out.quantity != nullptr && core::needs_mode(out.quantity->observable);
    if (const auto* mode = reader.find("mode")) {
        if (out.quantity != nullptr && !modal) {
            errors.add({reader.at("mode"),
                        concat("applies to natural_frequency_Hz and damping_ratio only, not to ",
                               out.quantity->name),
                        std::nullopt, std::nullopt});
            ok = false;
        } else {
            const OptionsReader mode_reader(*mode, reader.at("mode"), mode_members, errors);
            if (!mode_reader.is_object()) return std::nullopt;
            const bool by_index = mode_reader.find("index") != nullptr;
            const bool by_frequency = mode_reader.find("near_frequency_Hz") != nullptr;
            if (by_index == by_frequency) {
                errors.add({mode_reader.pointer(),
                            "give exactly one of index and near_frequency_Hz", std::nullopt,
                            std::nullopt});
                ok = false;
            } else if (by_index) {
                ok = mode_reader.integer("index", closed(0.0, 5.0), out.mode.index) && ok;
            } else {
                ok = mode_reader.number("near_frequency_Hz", units::hertz, open_closed(0.0, 1e5),
                                        out.mode.near_Hz) &&
                     ok;
            }
        }
    } else if (modal) {
        errors.add(
            {reader.at("mode"),
             "required for a mode's quantity: {\"index\": i} (0..5, ascending natural frequency at the start "
             "values) or {\"near_frequency_Hz\": f}",
             std::nullopt, std::nullopt});
        ok = false;
    }
    if (!ok) return std::nullopt;
    out.echo = {{"scenario", out.patch},
                {"quantity", out.quantity->name},
                {"value", from_si(out.value, unit)},
                {"standard_uncertainty", from_si(out.uncertainty, unit)}};
    if (modal) {
        out.echo["mode"] = out.mode.index >= 0
                               ? nlohmann::json{{"index", out.mode.index}}
                               : nlohmann::json{{"near_frequency_Hz", out.mode.near_Hz}};
    }
    return out;
}

// Whether a merge patch sets `path` (a field pointer relative to the scenario).
bool patch_sets(const nlohmann::json& patch, const std::string& path) {
    const nlohmann::json::json_pointer location(path);
    return patch.is_object() && patch.contains(location);
}

template <class Read, class Reader>
std::vector<Read> read_list(const OptionsReader& options, std::string_view name, int cap,
                            std::string_view what, Reader read_one) {
    std::vector<Read> out;
    const std::string pointer = options.at(name);
    const nlohmann::json* list = options.find(name);
    const std::string bound = concat("1 to ", std::to_string(cap), " ", what);
    if (list == nullptr || !list->is_array() || list->empty() ||
        list->size() > static_cast<std::size_t>(cap)) {
        const std::string got = list == nullptr ? std::string("missing")
                                : !list->is_array()
                                    ? concat("a ", json_type_name(*list))
                                    : concat(std::to_string(list->size()), " ", what);
        options.errors().add(
            {pointer, concat("required: an array of ", bound, "; got ", got), bound, std::nullopt});
        return out;
    }
    for (std::size_t i = 0; i < list->size(); ++i) {
        if (auto read = read_one((*list)[i], append_pointer(pointer, std::to_string(i)),
                                 options.errors())) {
            out.push_back(std::move(*read));
        } else {
            out.emplace_back();  // keeps indices aligned; the request is invalid anyway
        }
    }
    return out;
}

}  // namespace

// The field a parameter names, or nullptr with the violation recorded at `pointer`.
const ScenarioField* read_fitted_field(const nlohmann::json* value, const std::string& pointer,
                                       FieldErrors& errors) {
    if (value == nullptr) {
        errors.add(
            {pointer,
             "required: the JSON pointer of the scenario field to fit, e.g. \"/strip/flow_stress_MPa\"",
             std::nullopt, std::nullopt});
        return nullptr;
    }
    const auto path = read_string(*value, pointer, errors);
    if (!path) return nullptr;
    const ScenarioField* field = find_scenario_field(*path);
    if (field != nullptr && field->kind == FieldKind::number) return field;
    std::string detail;
    if (field != nullptr) {
        detail =
            concat(quoted_for_message(*path), " is not a continuous number field; a fit needs one");
    } else if (is_scenario_group(*path)) {
        detail = concat(quoted_for_message(*path), " is a group of fields, not a field");
    } else {
        detail = concat(quoted_for_message(*path),
                        " is not a field of the scenario (as 'rollgap scenario' prints it)");
        detail += did_you_mean(*path, fittable_paths());
    }
    errors.add({pointer, std::move(detail), choices_text(fittable_paths()), std::nullopt});
    return nullptr;
}

const std::vector<CalibrationQuantity>& calibration_quantities() {
    static const std::vector<CalibrationQuantity> table{
        {"roll_force_kN", core::Observable::roll_force, units::kilonewton, "Roll force"},
        {"torque_kN_m", core::Observable::torque, units::kilonewton_metre,
         "Rolling torque per work roll"},
        {"forward_slip", core::Observable::forward_slip, units::one, "Forward slip"},
        {"critical_speed_m_per_s", core::Observable::critical_speed, units::metre_per_second,
         "Critical speed"},
        {"chatter_frequency_Hz", core::Observable::chatter_frequency, units::hertz,
         "Chatter frequency"},
        {"natural_frequency_Hz", core::Observable::natural_frequency, units::hertz,
         "Natural frequency of a mode"},
        {"damping_ratio", core::Observable::damping_ratio, units::one, "Damping ratio of a mode"},
        {"running_frequency_Hz", core::Observable::running_frequency, units::hertz,
         "Frequency of the running stand's least-damped mode"},
        {"running_damping_ratio", core::Observable::running_damping_ratio, units::one,
         "Damping ratio of the running stand's least-damped mode"},
    };
    return table;
}

CalibrationPlan calibration_plan_from_json(const nlohmann::json& options,
                                           const std::string& pointer,
                                           const core::Scenario* valid_scenario,
                                           FieldErrors& errors) {
    CalibrationPlan plan;
    const OptionsReader reader(options, pointer, option_members, errors);
    if (!reader.is_object()) return plan;
    const std::size_t errors_before = errors.size();

    const auto parameters = read_list<ParameterRead>(
        reader, "parameters", max_calibration_parameters, "parameters", read_parameter);
    const auto observations = read_list<ObservationRead>(
        reader, "observations", max_calibration_observations, "observations", read_observation);
    int max_iterations = 30;
    reader.read(OptionId::max_iterations, max_iterations);
    plan.setup.critical_speed = critical_speed_options_from_json(
        reader.object_or_defaults("critical_speed"), reader.at("critical_speed"), errors);

    // The same field twice would be one parameter with two names: the normal matrix singular.
    for (std::size_t i = 0; i < parameters.size(); ++i) {
        for (std::size_t k = 0; k < i; ++k) {
            if (parameters[i].field != nullptr && parameters[i].field == parameters[k].field) {
                errors.add(
                    {append_pointer(append_pointer(reader.at("parameters"), std::to_string(i)),
                                    "field"),
                     concat(parameters[i].field->path, " is already parameter ", std::to_string(k)),
                     std::nullopt, std::nullopt});
            }
        }
    }

    // A stored posterior as the prior of the parameters it covers (docs/model.md §11.6).
    std::optional<Posterior> joint;
    if (const nlohmann::json* value = reader.find("joint_prior"))
        joint = read_posterior(*value, reader.at("joint_prior"), nullptr, errors);
    if (joint && !errors.has_error_at_or_below(reader.at("parameters"))) {
        core::JointPrior prior;
        prior.mean = joint->mean;
        prior.covariance = joint->covariance();
        for (std::size_t k = 0; k < joint->fields.size(); ++k) {
            const std::string at = append_pointer(
                append_pointer(append_pointer(reader.at("joint_prior"), "parameters"),
                               std::to_string(k)),
                "field");
            const auto fitted =
                std::find_if(parameters.begin(), parameters.end(),
                             [&](const ParameterRead& p) { return p.field == joint->fields[k]; });
            if (fitted == parameters.end()) {
                errors.add({at,
                            concat(joint->fields[k]->path,
                                   " is not fitted: a prior is on fitted parameters; add it to "
                                   "options.parameters or leave it out of the joint prior"),
                            std::nullopt, std::nullopt});
                continue;
            }
            if (fitted->parameter.has_prior) {
                errors.add(
                    {append_pointer(append_pointer(reader.at("parameters"),
                                                   std::to_string(fitted - parameters.begin())),
                                    "prior"),
                     concat(joint->fields[k]->path,
                            " has the joint prior already: give it one prior, not two"),
                     std::nullopt, std::nullopt});
            }
            prior.indices.push_back(static_cast<int>(fitted - parameters.begin()));
        }
        if (prior.covariance.llt().info() != Eigen::Success) {
            errors.add({append_pointer(reader.at("joint_prior"), "correlation"),
                        "makes the prior's covariance singular: a prior needs a positive definite "
                        "one (no correlation of ±1)",
                        std::nullopt, std::nullopt});
        }
        plan.setup.joint_prior = std::move(prior);
    }

    nlohmann::json parameter_echo = nlohmann::json::array(),
                   observation_echo = nlohmann::json::array();
    for (const auto& p : parameters) parameter_echo.push_back(p.echo);
    for (const auto& o : observations) observation_echo.push_back(o.echo);

    const int n = static_cast<int>(parameters.size());
    plan.setup.options.max_iterations = max_iterations;
    plan.setup.options.max_evaluations = max_iterations * (n + 4) + 2 * n + 2;
    plan.resolved_options = {
        {"parameters", std::move(parameter_echo)},
        {"observations", std::move(observation_echo)},
        {option_name(OptionId::max_iterations), max_iterations},
        {"critical_speed", critical_speed_options_json(plan.setup.critical_speed)},
        {"joint_prior", joint ? posterior_json(*joint) : nlohmann::json(nullptr)}};
    if (errors.size() != errors_before || valid_scenario == nullptr) return plan;

    // Start values inside their boxes; conditions read like scenarios.
    plan.scenario = *valid_scenario;
    core::Scenario start = *valid_scenario;
    for (std::size_t j = 0; j < parameters.size(); ++j) {
        const ParameterRead& p = parameters[j];
        core::CalibrationParameter parameter = p.parameter;
        parameter.start = p.field->number(start);
        if (parameter.start < parameter.lower || parameter.start > parameter.upper) {
            const std::string at = append_pointer(reader.at("parameters"), std::to_string(j));
            errors.add({append_pointer(at, parameter.start < parameter.lower ? "min" : "max"),
                        concat("the start value, the scenario's ", p.field->path, " = ",
                               format_number(from_si(parameter.start, p.field->unit)),
                               ", lies outside [min, max]"),
                        concat("[", format_number(from_si(parameter.lower, p.field->unit)), ", ",
                               format_number(from_si(parameter.upper, p.field->unit)), "]"),
                        std::string(p.field->unit.code)});
        }
        plan.fields.push_back(p.field);
        plan.setup.parameters.push_back(parameter);
        plan.setup.access.push_back(p.field->number);
    }
    const nlohmann::json base = resolved_scenario_json(start);
    std::vector<nlohmann::json> condition_documents;
    for (std::size_t i = 0; i < observations.size(); ++i) {
        const ObservationRead& o = observations[i];
        for (const ScenarioField* field : plan.fields) {
            if (patch_sets(o.patch, field->path)) {
                errors.add(
                    {concat(o.patch_pointer, field->path),
                     "is a fitted parameter: the fit sets it in every observation's conditions; remove it here",
                     std::nullopt, std::nullopt});
            }
        }
        nlohmann::json document = base;
        document.merge_patch(o.patch);
        FieldErrors condition_errors;
        const core::Scenario condition =
            scenario_from_json(document, o.patch_pointer, condition_errors);
        for (const FieldError& error : condition_errors.reported()) errors.add(error);
        const auto same =
            std::find(condition_documents.begin(), condition_documents.end(), document);
        int index = static_cast<int>(same - condition_documents.begin());
        if (same == condition_documents.end()) {
            condition_documents.push_back(std::move(document));
            plan.setup.conditions.push_back(condition);
        }
        plan.setup.observations.push_back(
            {index, o.quantity->observable, o.value, o.uncertainty, o.mode});
        plan.quantity_names.emplace_back(o.quantity->name);
        plan.quantity_units.push_back(o.quantity->unit);
    }
    if (!errors.empty()) return plan;

    plan.estimated_stability_evaluations = static_cast<long>(plan.setup.options.max_evaluations) *
                                           core::stability_evaluations_per_prediction(plan.setup);
    if (plan.estimated_stability_evaluations > max_calibration_stability_evaluations) {
        const long per_evaluation = core::stability_evaluations_per_prediction(plan.setup);
        const long evaluations = max_calibration_stability_evaluations / per_evaluation;
        const int iterations = static_cast<int>((evaluations - 2 * n - 2) / (n + 4));
        errors.add(
            {reader.at(option_name(OptionId::max_iterations)),
             concat(
                 "up to ", std::to_string(plan.setup.options.max_evaluations), " evaluations × ",
                 std::to_string(per_evaluation),
                 " stability evaluations each (critical-speed searches) = ",
                 std::to_string(plan.estimated_stability_evaluations), "; a fit may do at most ",
                 std::to_string(max_calibration_stability_evaluations),
                 ": fewer iterations, fewer conditions with critical-speed observations, or a narrower or "
                 "coarser critical_speed search"),
             iterations >= 1 ? concat("[1, ", std::to_string(iterations), "]")
                             : std::string("none"),
             std::nullopt});
    }
    return plan;
}

}  // namespace rollgap::api
