#pragma once
// A calibration posterior as a request carries it (docs/model.md §13.3): the fitted fields with
// their posterior means and standard errors in the fields' units, and their correlation, in the
// shape calibrate's result lists them (its other parameter members are accepted and ignored).
// speed_limit reads it as the scenario's uncertainty; calibrate as a joint prior (§11.6).

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/scenario_schema.h"
#include "core/scenario.h"

namespace rollgap::api {

inline constexpr int max_posterior_parameters = 12;

// Fitted scenario fields with their joint Gaussian uncertainty, in SI.
struct Posterior {
    std::vector<const ScenarioField*> fields;
    Eigen::VectorXd mean;
    Eigen::VectorXd standard_errors;
    Eigen::MatrixXd correlation;

    Eigen::MatrixXd covariance() const {
        return standard_errors.asDiagonal() * correlation * standard_errors.asDiagonal();
    }
    // The scenario with the fields at x (SI).
    core::Scenario at(const core::Scenario& scenario, const Eigen::VectorXd& x) const;
};

// {parameters: [{field, value, standard_error}], correlation}: number fields of the scenario,
// none twice, standard errors > 0, the unit if given the field's, the correlation n × n,
// symmetric, unit diagonal, in [-1, 1], positive semidefinite (absent or null: uncorrelated).
// `centre`: the values must be this scenario's (to 1e-9), else nullptr. null: nullopt, no error.
// `stand_pointer`: the centre is a tandem document's stand there ("/stands/1"), so a value
// elsewhere is answered in the document's terms.
std::optional<Posterior> read_posterior(const nlohmann::json& value, const std::string& pointer,
                                        const core::Scenario* centre, FieldErrors& errors,
                                        std::string_view stand_pointer = {});
nlohmann::json posterior_json(const Posterior& posterior);

}  // namespace rollgap::api
