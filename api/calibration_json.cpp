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
#include "api/options_reader.h"
#include "api/quantity_json.h"
#include "api/result_table.h"
#include "api/scenario_json.h"
#include "api/stability_json.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

constexpr std::array<std::string_view, 4> option_members{"parameters", "observations",
                                                         "max_iterations", "critical_speed"};
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

// The field a parameter names, or nullptr with the violation recorded at `pointer`.
const ScenarioField* read_field(const nlohmann::json* value, const std::string& pointer,
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
    out.field = read_field(reader.find("field"), reader.at("field"), errors);
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
    if (const auto* prior = reader.find("prior")) {
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
    if (const auto* patch = reader.find("scenario")) {
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

const std::vector<CalibrationQuantity>& calibration_quantities() {
    static const std::vector<CalibrationQuantity> table{
        {"roll_force_kN", core::Observable::roll_force, units::kilonewton},
        {"torque_kN_m", core::Observable::torque, units::kilonewton_metre},
        {"forward_slip", core::Observable::forward_slip, units::one},
        {"critical_speed_m_per_s", core::Observable::critical_speed, units::metre_per_second},
        {"chatter_frequency_Hz", core::Observable::chatter_frequency, units::hertz},
        {"natural_frequency_Hz", core::Observable::natural_frequency, units::hertz},
        {"damping_ratio", core::Observable::damping_ratio, units::one},
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
    reader.integer("max_iterations", closed(1.0, max_calibration_iterations), max_iterations);
    const nlohmann::json* search = reader.find("critical_speed");
    plan.setup.critical_speed =
        critical_speed_options_from_json(search != nullptr ? *search : nlohmann::json::object(),
                                         reader.at("critical_speed"), errors);

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
        {"max_iterations", max_iterations},
        {"critical_speed", critical_speed_options_json(plan.setup.critical_speed)}};
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
            {reader.at("max_iterations"),
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

nlohmann::json merge_patch_between(const nlohmann::json& from, const nlohmann::json& to) {
    if (!from.is_object() || !to.is_object()) return to;
    nlohmann::json patch = nlohmann::json::object();
    for (const auto& [key, value] : from.items()) {
        if (!to.contains(key)) patch[key] = nullptr;
    }
    for (const auto& [key, value] : to.items()) {
        const auto old = from.find(key);
        if (old == from.end()) {
            patch[key] = value;
        } else if (*old != value) {
            patch[key] =
                old->is_object() && value.is_object() ? merge_patch_between(*old, value) : value;
        }
    }
    return patch;
}

namespace {

double fifteen_digits(double value) {
    std::array<char, 32> text{};
    const auto written = std::to_chars(text.data(), text.data() + text.size(), value,
                                       std::chars_format::general, 15);
    double rounded = value;
    std::from_chars(text.data(), written.ptr, rounded);
    return rounded;
}

nlohmann::json number_or_null(double value) {
    return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

std::string field_list(const CalibrationPlan& plan, const std::vector<int>& indices) {
    std::string text;
    for (const int j : indices) {
        if (!text.empty()) text += ", ";
        text += plan.fields[static_cast<std::size_t>(j)]->path;
    }
    return text;
}

nlohmann::json field_array(const CalibrationPlan& plan, const std::vector<int>& indices) {
    nlohmann::json fields = nlohmann::json::array();
    for (const int j : indices) fields.push_back(plan.fields[static_cast<std::size_t>(j)]->path);
    return fields;
}

}  // namespace

namespace {

nlohmann::json plain_number_schema(bool nullable) {
    return {
        {"type", nullable ? nlohmann::json::array({"number", "null"}) : nlohmann::json("number")}};
}

// The figures of one fitted parameter, in the field's unit.
struct ParameterRow {
    const ScenarioField* field = nullptr;
    double start = 0.0, value = 0.0, min = 0.0, max = 0.0;
    nlohmann::json standard_error, prior_normalised_residual;
    const char* at_bound = nullptr;
};

struct ObservationRow {
    std::string_view quantity;
    double value = 0.0, standard_uncertainty = 0.0;
    nlohmann::json predicted, normalised_residual, failure;
    std::optional<std::pair<double, double>> mode;  // start frequency (Hz), shape agreement (MAC)
};

struct Warning {
    std::string_view code;
    nlohmann::json fields;
    std::string detail;
};

struct CalibrationOutput {
    const CalibrationPlan& plan;
    const core::CalibrationResult& fit;
    std::vector<ParameterRow> parameters;
    nlohmann::json correlation;
    std::vector<ObservationRow> observations;
    std::vector<Warning> warnings;
    nlohmann::json calibrated_scenario;
};

const ResultTable<ParameterRow>& parameter_table() {
    static const ResultTable<ParameterRow> table{
        "CalibratedParameter",
        "One fitted scenario field; its figures in the field's unit (`unit`).",
        {
            {"field", "The scenario field's JSON pointer.", string_schema(),
             [](const ParameterRow& r) { return nlohmann::json(r.field->path); }},
            {"unit", "The field's unit (UCUM code).", string_schema(),
             [](const ParameterRow& r) { return nlohmann::json(r.field->unit.code); }},
            {"start", "The start value: the request scenario's.", plain_number_schema(false),
             [](const ParameterRow& r) { return nlohmann::json(r.start); }},
            {"value", "The fitted value, 15 significant digits (as in calibrated_scenario).",
             plain_number_schema(false),
             [](const ParameterRow& r) { return nlohmann::json(r.value); }},
            {"standard_error",
             "Standard error of the value from the posterior covariance; null without statistics.",
             plain_number_schema(true), [](const ParameterRow& r) { return r.standard_error; }},
            {"min", "The lower bound the fit kept to.", plain_number_schema(false),
             [](const ParameterRow& r) { return nlohmann::json(r.min); }},
            {"max", "The upper bound the fit kept to.", plain_number_schema(false),
             [](const ParameterRow& r) { return nlohmann::json(r.max); }},
            {"at_bound", "The bound the value stopped at, or null.",
             enum_schema({"min", "max"}, true),
             [](const ParameterRow& r) {
                 return r.at_bound != nullptr ? nlohmann::json(r.at_bound)
                                              : nlohmann::json(nullptr);
             }},
            {"prior_normalised_residual",
             "(value - prior) / prior uncertainty; null without a prior.",
             plain_number_schema(true),
             [](const ParameterRow& r) { return r.prior_normalised_residual; }},
        }};
    return table;
}

const ResultTable<ObservationRow>& observation_table() {
    static const ResultTable<ObservationRow> table{
        "CalibrationObservation",
        "One observation and the calibrated model's prediction of it, in the quantity's unit (its name carries it).",
        {
            {"quantity", "The observed quantity, as in the request.", string_schema(),
             [](const ObservationRow& r) { return nlohmann::json(r.quantity); }},
            {"value", "The observed value.", plain_number_schema(false),
             [](const ObservationRow& r) { return nlohmann::json(r.value); }},
            {"standard_uncertainty", "The observation's standard uncertainty.",
             plain_number_schema(false),
             [](const ObservationRow& r) { return nlohmann::json(r.standard_uncertainty); }},
            {"predicted", "The calibrated model's value; null when the model had no answer.",
             plain_number_schema(true), [](const ObservationRow& r) { return r.predicted; }},
            {"normalised_residual",
             "(predicted - value) / standard_uncertainty; null without a prediction.",
             plain_number_schema(true),
             [](const ObservationRow& r) { return r.normalised_residual; }},
            {"failure",
             "Why the model had no answer, or null.",
             {{"type", nlohmann::json::array({"string", "null"})}},
             [](const ObservationRow& r) { return r.failure; }},
            {"mode",
             "The mode the observation followed (natural_frequency_Hz and damping_ratio only).",
             object_schema("The followed mode.",
                           {{"start_frequency_Hz", number_schema(units::hertz)},
                            {"shape_agreement_mac", number_schema(units::one)}},
                           {"start_frequency_Hz", "shape_agreement_mac"}),
             [](const ObservationRow& r) {
                 if (!r.mode) return absent();
                 return nlohmann::json{{"start_frequency_Hz", number_or_null(r.mode->first)},
                                       {"shape_agreement_mac", number_or_null(r.mode->second)}};
             },
             true},
        }};
    return table;
}

const ResultTable<Warning>& warning_table() {
    static const ResultTable<Warning> table{
        "CalibrationWarning",
        "Something the fit could not determine as asked.",
        {
            {"code",
             "`at_bound`: a field stopped at a bound. `inseparable`: the observations determine only a combination "
             "of the fields. `unobservable`: no observation depends on the fields.",
             enum_schema({"at_bound", "inseparable", "unobservable"}),
             [](const Warning& w) { return nlohmann::json(w.code); }},
            {"fields", "The scenario fields concerned.", array_schema(string_schema()),
             [](const Warning& w) { return w.fields; }},
            {"detail", "What it means and what to do, for humans.", string_schema(),
             [](const Warning& w) { return nlohmann::json(w.detail); }},
        }};
    return table;
}

template <class Row>
nlohmann::json rows_json(const ResultTable<Row>& table, const std::vector<Row>& rows) {
    nlohmann::json out = nlohmann::json::array();
    for (const Row& row : rows) out.push_back(table.write(row));
    return out;
}

const ResultTable<CalibrationOutput>& calibration_result_table() {
    using O = CalibrationOutput;
    static const ResultTable<O> table{
        "CalibrationResult",
        "The fit of scenario fields to plant observations by weighted least squares (docs/model.md §11).",
        {
            {"status",
             "`converged`: the tolerances are met. `max_iterations`, `max_evaluations`: a limit stopped the fit. "
             "`stalled`: no step lowers chi-squared any more. `model_failure`: the model has no answer at the "
             "start values. `cancelled`: the job was cancelled.",
             enum_schema({"converged", "max_iterations", "max_evaluations", "stalled",
                          "model_failure", "cancelled"}),
             [](const O& o) { return nlohmann::json(core::to_string(o.fit.status)); }},
            {"iterations", "Gauss-Newton iterations done.", integer_schema(),
             [](const O& o) { return nlohmann::json(o.fit.iterations); }},
            {"evaluations", "Evaluations of all observations done.", integer_schema(),
             [](const O& o) { return nlohmann::json(o.fit.evaluations); }},
            {"work_bound_stability_evaluations",
             "The bound on the linearisations the fit could need, checked before it ran.",
             integer_schema(),
             [](const O& o) { return nlohmann::json(o.plan.estimated_stability_evaluations); }},
            {"parameters", "The fitted fields, in the order of options.parameters.",
             array_schema(ref_schema("CalibratedParameter")),
             [](const O& o) { return rows_json(parameter_table(), o.parameters); }},
            {"covariance", "How the standard errors and correlations were obtained.",
             string_schema(),
             [](const O&) {
                 return nlohmann::json(
                     "posterior: from the Jacobian of the observations and the priors at the solution");
             }},
            {"correlation",
             "Correlation matrix of the parameters (rows and columns as parameters); null without statistics.",
             array_schema(array_schema(number_schema(units::one))),
             [](const O& o) { return o.correlation; }},
            {"observations", "The observations, in the order of options.observations.",
             array_schema(ref_schema("CalibrationObservation")),
             [](const O& o) { return rows_json(observation_table(), o.observations); }},
            {"chi_squared_observations",
             "Sum of the squared normalised residuals of the observations.",
             plain_number_schema(false),
             [](const O& o) { return nlohmann::json(o.fit.chi_squared_observations); }},
            {"chi_squared_priors", "Sum of the squared normalised residuals of the priors.",
             plain_number_schema(false),
             [](const O& o) { return nlohmann::json(o.fit.chi_squared_priors); }},
            {"degrees_of_freedom", "Observations and priors minus parameters.", integer_schema(),
             [](const O& o) { return nlohmann::json(o.fit.degrees_of_freedom); }},
            {"reciprocal_condition",
             "Reciprocal condition number of the scaled normal matrix (1: well separated).",
             plain_number_schema(false),
             [](const O& o) { return nlohmann::json(o.fit.reciprocal_condition); }},
            {"warnings", "What the fit could not determine as asked.",
             array_schema(ref_schema("CalibrationWarning")),
             [](const O& o) { return rows_json(warning_table(), o.warnings); }},
            {"calibrated_scenario",
             "The calibrated scenario as a merge patch onto the defaults: a scenario to send with later requests.",
             ref_schema("ScenarioPatch"), [](const O& o) { return o.calibrated_scenario; }},
        }};
    return table;
}

}  // namespace

std::vector<ResultSchema> calibration_result_schemas() {
    return {result_schema(parameter_table()), result_schema(observation_table()),
            result_schema(warning_table()), result_schema(calibration_result_table())};
}

std::vector<std::string> calibration_parameter_columns() {
    return parameter_table().scalar_names();
}
std::vector<std::string> calibration_observation_columns() {
    return observation_table().scalar_names();
}

nlohmann::json calibration_result_json(const CalibrationPlan& plan,
                                       const core::ScenarioCalibrationResult& result) {
    const core::CalibrationResult& fit = result.fit;
    const std::size_t n = plan.fields.size();
    CalibrationOutput output{plan, fit, {}, nlohmann::json::array(), {}, {}, {}};
    core::Scenario calibrated = plan.scenario;
    for (std::size_t j = 0; j < n; ++j) {
        const ScenarioField& field = *plan.fields[j];
        const core::CalibrationParameter& p = plan.setup.parameters[j];
        const auto J = static_cast<Eigen::Index>(j);
        // 15 significant digits (far below the fit's precision): a value that reads back from
        // the calibrated scenario as the same double, so a rerun echoes exactly these values.
        const double value = to_si(fifteen_digits(from_si(fit.values(J), field.unit)), field.unit);
        field.number(calibrated) = value;
        const bool have_statistics = fit.standard_errors.size() == static_cast<Eigen::Index>(n);
        const core::BoundState bound =
            j < fit.bounds.size() ? fit.bounds[j] : core::BoundState::inside;
        const char* bound_name = bound == core::BoundState::lower   ? "min"
                                 : bound == core::BoundState::upper ? "max"
                                                                    : nullptr;
        output.parameters.push_back({
            &field,
            from_si(p.start, field.unit),
            from_si(value, field.unit),
            from_si(p.lower, field.unit),
            from_si(p.upper, field.unit),
            have_statistics ? quantity_json(fit.standard_errors(J), field.unit)
                            : nlohmann::json(nullptr),
            p.has_prior && fit.prior_residuals.size() == static_cast<Eigen::Index>(n)
                ? nlohmann::json(fit.prior_residuals(J))
                : nlohmann::json(nullptr),
            bound_name,
        });
        if (bound_name != nullptr) {
            output.warnings.push_back(
                {"at_bound",
                 {field.path},
                 concat(field.path, " stopped at its ", bound_name, " (",
                        format_number(from_si(value, field.unit)), " ", field.unit.code,
                        "): the observations ask for a value beyond it; its standard error "
                        "is the curvature there, not a two-sided interval")});
        }
    }
    for (std::size_t a = 0; a < n; ++a) {
        nlohmann::json row = nlohmann::json::array();
        for (std::size_t b = 0; b < n; ++b) {
            row.push_back(fit.correlation.rows() == static_cast<Eigen::Index>(n)
                              ? number_or_null(fit.correlation(static_cast<Eigen::Index>(a),
                                                               static_cast<Eigen::Index>(b)))
                              : nlohmann::json(nullptr));
        }
        output.correlation.push_back(std::move(row));
    }
    for (const auto& group : fit.inseparable) {
        output.warnings.push_back(
            {"inseparable", field_array(plan, group),
             concat("the observations determine only a combination of ", field_list(plan, group),
                    " (reciprocal condition number ", format_number(fit.reciprocal_condition),
                    "): add observations that move them differently, or priors")});
    }
    if (!fit.unobservable.empty()) {
        output.warnings.push_back(
            {"unobservable", field_array(plan, fit.unobservable),
             concat("no observation depends on ", field_list(plan, fit.unobservable),
                    ": only a prior determines it")});
    }

    for (std::size_t i = 0; i < plan.setup.observations.size(); ++i) {
        const core::ScenarioObservation& o = plan.setup.observations[i];
        const Unit unit = plan.quantity_units[i];
        const core::ObservationPrediction* p =
            i < result.predictions.size() ? &result.predictions[i] : nullptr;
        ObservationRow row{
            plan.quantity_names[i],
            from_si(o.value, unit),
            from_si(o.uncertainty, unit),
            p != nullptr ? quantity_json(p->value, unit) : nlohmann::json(nullptr),
            p != nullptr && std::isfinite(p->value)
                ? nlohmann::json((p->value - o.value) / o.uncertainty)
                : nlohmann::json(nullptr),
            p != nullptr && !p->failure.empty() ? nlohmann::json(p->failure)
                                                : nlohmann::json(nullptr),
            std::nullopt,
        };
        if (core::needs_mode(o.quantity) && p != nullptr)
            row.mode = std::pair{p->mode_frequency_Hz, p->mode_mac};
        output.observations.push_back(std::move(row));
    }
    output.calibrated_scenario =
        merge_patch_between(default_scenario_json(), resolved_scenario_json(calibrated));
    return calibration_result_table().write(output);
}

}  // namespace rollgap::api
