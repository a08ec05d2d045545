// Reading and writing a calibration posterior (api/posterior_json.h).
#include "api/posterior_json.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

#include <Eigen/Eigenvalues>

#include "api/calibration_json.h"
#include "api/options_reader.h"
#include "api/text.h"
#include "api/units.h"

namespace rollgap::api {
namespace {

using std::string_view_literals::operator""sv;

constexpr std::array<std::string_view, 2> posterior_members{"parameters"sv, "correlation"sv};
// A parameter as calibrate writes it: field, value and standard_error are read, unit is checked,
// the rest is what the fit reports about itself and is ignored here.
constexpr std::array<std::string_view, 9> posterior_parameter_members{
    "field"sv, "value"sv,    "standard_error"sv,           "unit"sv, "start"sv, "min"sv,
    "max"sv,   "at_bound"sv, "prior_normalised_residual"sv};

// Whose field a posterior's value disagrees with, and what to send instead: the scenario's, or
// (`stand_pointer` given, e.g. "/stands/1") one stand's of a tandem document, whose values are
// /stand_defaults with that stand's patch merged over them.
std::string posterior_centre_text(std::string_view stand_pointer, std::string_view path) {
    if (stand_pointer.empty()) return concat("the scenario's ", path);
    return concat("the stand's ", path, " (", stand_pointer, " over /stand_defaults)");
}

std::string posterior_remedy_text(std::string_view stand_pointer) {
    if (stand_pointer.empty())
        return ": send calibrate's calibrated_scenario as the scenario with its posterior";
    return concat(": merge calibrate's calibrated_scenario for this stand into ", stand_pointer,
                  " and send its posterior with it");
}

// The posterior's parameters: each a scenario number field with a value at the scenario's and a
// standard error > 0, no field twice.
void read_parameters(const nlohmann::json& list, const std::string& pointer,
                     const core::Scenario* scenario, std::string_view stand_pointer, Posterior& out,
                     FieldErrors& errors) {
    if (!list.is_array() || list.empty() ||
        list.size() > static_cast<std::size_t>(max_posterior_parameters)) {
        errors.add({pointer,
                    concat("must be an array of 1 to ", std::to_string(max_posterior_parameters),
                           " fitted parameters, as calibrate's result.parameters lists them"),
                    concat("[1, ", std::to_string(max_posterior_parameters), "] items"),
                    std::nullopt});
        return;
    }
    const std::size_t n = list.size();
    out.fields.assign(n, nullptr);
    out.mean = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
    out.standard_errors = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
    for (std::size_t i = 0; i < n; ++i) {
        const std::string at = concat(pointer, "/", std::to_string(i));
        const OptionsReader reader(list[i], at, posterior_parameter_members, errors);
        if (!reader.is_object()) continue;
        const ScenarioField* field =
            read_fitted_field(reader.find("field"), reader.at("field"), errors);
        if (field == nullptr) continue;
        out.fields[i] = field;
        for (std::size_t k = 0; k < i; ++k) {
            if (out.fields[k] == field) {
                errors.add({reader.at("field"),
                            concat(field->path, " is already parameter ", std::to_string(k)),
                            std::nullopt, std::nullopt});
            }
        }
        if (const nlohmann::json* unit = reader.find("unit")) {
            if (!unit->is_string() || unit->get_ref<const std::string&>() != field->unit.code) {
                errors.add({reader.at("unit"),
                            concat("the unit of ", field->path, " is ", field->unit.code,
                                   "; the value and standard error are read in it"),
                            std::string(field->unit.code), std::string(field->unit.code)});
            }
        }
        double value = 0.0, sigma = 0.0;
        const bool has_value = reader.number("value", field->unit, field->range, value);
        if (reader.find("value") == nullptr) {
            errors.add({reader.at("value"),
                        concat("required, in the field's unit (", field->unit.code, ")"),
                        std::nullopt, std::string(field->unit.code)});
        }
        const bool has_sigma =
            reader.number("standard_error", field->unit, open_closed(0.0, 1e300), sigma);
        if (reader.find("standard_error") == nullptr) {
            errors.add({reader.at("standard_error"),
                        concat("required: the fitted value's standard error, in the field's unit (",
                               field->unit.code, "), > 0"),
                        "(0, 1e+300]", std::string(field->unit.code)});
        }
        if (has_value) {
            out.mean(static_cast<Eigen::Index>(i)) = value;
            // The posterior is centred on the scenario: a value elsewhere would describe another
            // stand than the one analysed.
            if (scenario != nullptr) {
                core::Scenario copy = *scenario;
                const double current = field->number(copy);
                if (std::abs(current - value) >
                    1e-9 * std::max(std::abs(current), std::abs(value))) {
                    errors.add(
                        {reader.at("value"),
                         concat("the posterior is centred at ",
                                format_number(from_si(value, field->unit)), " ", field->unit.code,
                                " but ", posterior_centre_text(stand_pointer, field->path), " is ",
                                format_number(from_si(current, field->unit)),
                                posterior_remedy_text(stand_pointer)),
                         std::nullopt, std::string(field->unit.code)});
                }
            }
        }
        if (has_sigma) out.standard_errors(static_cast<Eigen::Index>(i)) = sigma;
    }
}

// The correlation: n × n, symmetric, unit diagonal, entries in [-1, 1], positive semidefinite
// (to rounding). Absent: the identity.
void read_correlation(const nlohmann::json* value, const std::string& pointer, std::size_t n,
                      Posterior& out, FieldErrors& errors) {
    const auto index = [](std::size_t i) { return static_cast<Eigen::Index>(i); };
    out.correlation = Eigen::MatrixXd::Identity(index(n), index(n));
    if (value == nullptr || value->is_null()) return;
    const std::string shape = concat(std::to_string(n), " × ", std::to_string(n));
    if (!value->is_array() || value->size() != n) {
        errors.add({pointer,
                    concat("must be the ", shape,
                           " correlation matrix of the parameters, as calibrate returns it"),
                    std::nullopt, std::nullopt});
        return;
    }
    bool ok = true;
    for (std::size_t i = 0; i < n; ++i) {
        const nlohmann::json& row = (*value)[i];
        const std::string row_at = concat(pointer, "/", std::to_string(i));
        if (!row.is_array() || row.size() != n) {
            errors.add({row_at, concat("must be a row of ", std::to_string(n), " numbers"),
                        std::nullopt, std::nullopt});
            ok = false;
            continue;
        }
        for (std::size_t k = 0; k < n; ++k) {
            const Interval range = i == k ? closed(1.0, 1.0) : closed(-1.0, 1.0);
            const auto r = read_number(row[k], concat(row_at, "/", std::to_string(k)), range,
                                       units::one, errors);
            if (r) out.correlation(index(i), index(k)) = *r;
            else ok = false;
        }
    }
    if (!ok) return;
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t k = 0; k < i; ++k) {
            if (std::abs(out.correlation(index(i), index(k)) -
                         out.correlation(index(k), index(i))) > 1e-9) {
                errors.add({concat(pointer, "/", std::to_string(i), "/", std::to_string(k)),
                            concat("must equal entry [", std::to_string(k), "][", std::to_string(i),
                                   "]: a correlation matrix is symmetric"),
                            std::nullopt, std::nullopt});
                return;
            }
        }
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(out.correlation);
    if (eigen.info() != Eigen::Success || eigen.eigenvalues().minCoeff() < -1e-6) {
        errors.add({pointer,
                    concat("is not positive semidefinite (smallest eigenvalue ",
                           format_number(eigen.eigenvalues().minCoeff()),
                           "): no joint distribution has these correlations"),
                    std::nullopt, std::nullopt});
    }
}

}  // namespace

std::optional<Posterior> read_posterior(const nlohmann::json& value, const std::string& pointer,
                                        const core::Scenario* scenario, FieldErrors& errors,
                                        std::string_view stand_pointer) {
    if (value.is_null()) return std::nullopt;
    const OptionsReader reader(value, pointer, posterior_members, errors);
    if (!reader.is_object()) return std::nullopt;
    const nlohmann::json* parameters = reader.find("parameters");
    if (parameters == nullptr) {
        errors.add({reader.at("parameters"),
                    "required: the fitted fields, each {field, value, standard_error} in the "
                    "field's unit (calibrate's result.parameters)",
                    std::nullopt, std::nullopt});
        return std::nullopt;
    }
    Posterior posterior;
    read_parameters(*parameters, reader.at("parameters"), scenario, stand_pointer, posterior,
                    errors);
    if (errors.has_error_at_or_below(reader.at("parameters"))) return std::nullopt;
    read_correlation(reader.find("correlation"), reader.at("correlation"), posterior.fields.size(),
                     posterior, errors);
    if (errors.has_error_at_or_below(reader.at("correlation"))) return std::nullopt;
    return posterior;
}

nlohmann::json posterior_json(const Posterior& posterior) {
    nlohmann::json parameters = nlohmann::json::array();
    for (std::size_t i = 0; i < posterior.fields.size(); ++i) {
        const ScenarioField& field = *posterior.fields[i];
        const auto j = static_cast<Eigen::Index>(i);
        parameters.push_back({{"field", field.path},
                              {"unit", field.unit.code},
                              {"value", echo(posterior.mean(j), field.unit)},
                              {"standard_error", echo(posterior.standard_errors(j), field.unit)}});
    }
    nlohmann::json correlation = nlohmann::json::array();
    for (Eigen::Index i = 0; i < posterior.correlation.rows(); ++i) {
        nlohmann::json row = nlohmann::json::array();
        for (Eigen::Index k = 0; k < posterior.correlation.cols(); ++k)
            row.push_back(posterior.correlation(i, k));
        correlation.push_back(std::move(row));
    }
    return {{"parameters", std::move(parameters)}, {"correlation", std::move(correlation)}};
}

core::Scenario Posterior::at(const core::Scenario& scenario, const Eigen::VectorXd& x) const {
    core::Scenario out = scenario;
    for (std::size_t i = 0; i < fields.size(); ++i)
        fields[i]->number(out) = x(static_cast<Eigen::Index>(i));
    return out;
}

}  // namespace rollgap::api
