// Writing the calibrate analysis' result (api/calibration_json.h): the fitted parameters,
// the observations against the model, warnings and the calibrated scenario as a patch; the
// options reader is in calibration_options_json.cpp.
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
