// Reading a mill's posteriors and writing what they do to its critical speed
// (api/tandem_uncertainty_json.h; docs/model.md §13.7).
#include "api/tandem_uncertainty_json.h"

#include <algorithm>
#include <cmath>

#include "api/result_json.h"
#include "api/speed_limit_json.h"
#include "api/tandem_change_json.h"
#include "api/tandem_result_json.h"
#include "api/text.h"
#include "core/propagation.h"

namespace rollgap::api {
// Named, not anonymous: the unity build puts this file beside the other tandem_*_json.cpp.
namespace tandem_uncertainty_detail {

using nlohmann::json;

struct UncertaintyView {
    const core::MillCriticalSpeeds& critical;
    const core::MillSpeedUncertainty& uncertainty;
    double confidence;
    const std::vector<std::optional<Posterior>>& posteriors;
};

struct UncertaintyRow {
    int stand;
    const ScenarioField* field;
    double value, standard_error, derivative;  // SI; derivative dV_c/dx, m/s per SI unit
};

const ResultTable<UncertaintyRow>& uncertainty_row_table() {
    static const ResultTable<UncertaintyRow> table{
        "TandemPropagatedParameter",
        "One stand's posterior parameter and what it contributes to the headline critical speed's "
        "uncertainty.",
        {
            {"stand", "The stand, from 1.", stand_number_schema(false),
             [](const UncertaintyRow& r) { return stand_number(r.stand); }},
            {"field", "The stand's scenario field, its JSON pointer.", string_schema(),
             [](const UncertaintyRow& r) { return json(r.field->path); }},
            {"unit", "The field's unit (UCUM code): of value and standard_error.", string_schema(),
             [](const UncertaintyRow& r) { return json(r.field->unit.code); }},
            {"value", "The posterior mean, in the field's unit.", number_schema(units::one, false),
             [](const UncertaintyRow& r) { return json(from_si(r.value, r.field->unit)); }},
            {"standard_error", "The posterior standard deviation, in the field's unit.",
             number_schema(units::one, false),
             [](const UncertaintyRow& r) {
                 return json(from_si(r.standard_error, r.field->unit));
             }},
            {"critical_speed_change_m_per_s",
             "dV_c/dx times the standard error: the headline critical speed's change for one "
             "standard error of this field, to first order.",
             number_schema(units::metre_per_second),
             [](const UncertaintyRow& r) {
                 const double change = r.derivative * r.standard_error;
                 return std::isfinite(change) ? json(change) : json(nullptr);
             }},
        }};
    return table;
}

const ResultTable<UncertaintyView>& uncertainty_table() {
    using R = UncertaintyView;
    static const ResultTable<R> table{
        "TandemCriticalSpeedUncertainty",
        "The headline critical speed's uncertainty from the stands' calibration posteriors "
        "(docs/model.md §13.7): linear, sigma² = g Σ gᵀ with the gradient by the implicit "
        "function theorem at the crossing, and the one-sided lower bound the chatter limit is "
        "taken at.",
        {
            {"propagated",
             "Whether the crossing's margin had an answer at every difference point (else sigma "
             "is not known and the chatter limit is V_c itself).",
             boolean_schema(), [](const R& r) { return json(r.uncertainty.ok); }},
            {"crossing", "The headline crossing the uncertainty is of.",
             enum_schema({"frozen", "delay_independent", "nominal_delay"}),
             [](const R& r) {
                 const int k = r.critical.headline;
                 return json(k == 0 ? "frozen" : k == 1 ? "delay_independent" : "nominal_delay");
             }},
            {"critical_speed_m_per_s", "The headline critical speed at the posterior mean.",
             number_schema(units::metre_per_second, false),
             [](const R& r) { return json(r.uncertainty.critical_speed); }},
            {"standard_deviation_m_per_s", "sigma = sqrt(g Σ gᵀ); null when not propagated.",
             number_schema(units::metre_per_second),
             [](const R& r) {
                 const core::MillSpeedUncertainty& u = r.uncertainty;
                 return u.ok ? json(u.standard_deviation) : json(nullptr);
             }},
            {"confidence", "Of the one-sided lower bound.", number_schema(units::one, false),
             [](const R& r) { return json(r.confidence); }},
            {"z", "The standard normal quantile at the confidence.",
             number_schema(units::one, false),
             [](const R& r) { return json(core::normal_quantile(r.confidence)); }},
            {"lower_bound_m_per_s",
             "V_c - z sigma: the headline critical speed is above it with the confidence; null "
             "when not propagated.",
             number_schema(units::metre_per_second),
             [](const R& r) {
                 const core::MillSpeedUncertainty& u = r.uncertainty;
                 return u.ok ? json(u.lower_bound) : json(nullptr);
             }},
            {"parameters",
             "Each stand's posterior parameters, from the entry, in each posterior's order.",
             array_schema(ref_schema("TandemPropagatedParameter")),
             [](const R& r) {
                 const core::MillSpeedUncertainty& u = r.uncertainty;
                 json rows = json::array();
                 Eigen::Index j = 0;
                 for (std::size_t i = 0; i < r.posteriors.size(); ++i) {
                     if (!r.posteriors[i]) continue;
                     const Posterior& p = *r.posteriors[i];
                     for (std::size_t k = 0; k < p.fields.size(); ++k, ++j) {
                         const auto at = static_cast<Eigen::Index>(k);
                         const double g = u.ok ? u.gradient(j) : std::nan("");
                         rows.push_back(
                             uncertainty_row_table().write({static_cast<int>(i), p.fields[k],
                                                            p.mean(at), p.standard_errors(at), g}));
                     }
                 }
                 return rows;
             }},
            {"sampled",
             "The headline critical speed at options.samples seeded draws from the posteriors "
             "(each draw's mill searched whole, its headline whichever crossing it is): the "
             "check on sigma; null when samples is 0.",
             ref_schema("SampledCriticalSpeed", true),
             [](const R& r) {
                 return r.uncertainty.sampled ? sampled_critical_speed_json(*r.uncertainty.sampled)
                                              : json(nullptr);
             }},
        }};
    return table;
}

}  // namespace tandem_uncertainty_detail

bool check_per_stand_list(const nlohmann::json& list, const std::string& pointer, int stands,
                          std::string_view item, std::string_view what, FieldErrors& errors) {
    if (list.is_array() && list.size() <= static_cast<std::size_t>(core::max_mill_stands) &&
        (stands <= 0 || list.size() == static_cast<std::size_t>(stands)))
        return true;
    const std::string count = stands > 0 ? std::to_string(stands) : std::string("N");
    errors.add({pointer,
                concat("must be an array of one ", item, " per stand (", count, " here)", what),
                concat(count, " items"), std::nullopt});
    return list.is_array();
}

std::optional<MillPosteriors> read_mill_posteriors(const nlohmann::json& list,
                                                   const std::string& pointer,
                                                   const core::Mill* mill, FieldErrors& errors) {
    const int stands = mill != nullptr ? mill->size() : 0;
    const bool counted = check_per_stand_list(
        list, pointer, stands, "entry",
        ": that stand's calibration posterior as calibrate returns it ({parameters, "
        "correlation}), or null for a stand known exactly",
        errors);
    if (!list.is_array()) return std::nullopt;
    // each entry read even when the count is wrong (every violation at once), at most a mill's
    // most stands
    const std::size_t read = std::min(list.size(), std::size_t{core::max_mill_stands});
    MillPosteriors out;
    out.stands.resize(read);
    bool ok = counted && stands > 0;
    for (std::size_t i = 0; i < read; ++i) {
        const std::string item = concat(pointer, "/", std::to_string(i));
        const bool known = mill != nullptr && i < mill->stands.size();
        out.stands[i] = read_posterior(list[i], item, known ? &mill->stands[i] : nullptr, errors,
                                       concat("/stands/", std::to_string(i)));
        if (!list[i].is_null() && !out.stands[i]) ok = false;
        if (!out.stands[i]) continue;
        for (std::size_t k = 0; k < out.stands[i]->fields.size(); ++k) {
            const std::string why = mill_given_field_message(out.stands[i]->fields[k]->path,
                                                             static_cast<int>(i), stands);
            if (why.empty()) continue;
            errors.add({concat(item, "/parameters/", std::to_string(k), "/field"), why,
                        std::nullopt, std::nullopt});
            ok = false;
        }
    }
    if (!ok) return std::nullopt;
    Eigen::Index size = 0;
    for (const std::optional<Posterior>& p : out.stands)
        if (p) size += static_cast<Eigen::Index>(p->fields.size());
    out.mill.covariance = Eigen::MatrixXd::Zero(size, size);
    Eigen::Index offset = 0;
    for (std::size_t i = 0; i < out.stands.size(); ++i) {
        if (!out.stands[i]) continue;
        const Posterior& p = *out.stands[i];
        for (const ScenarioField* field : p.fields)
            out.mill.numbers.push_back(
                {[field, i](core::Mill& m, double delta) { field->number(m.stands[i]) += delta; },
                 0.0});
        const auto n = static_cast<Eigen::Index>(p.fields.size());
        out.mill.covariance.block(offset, offset, n, n) = p.covariance();
        offset += n;
    }
    return out;
}

nlohmann::json mill_uncertainty_json(const core::MillCriticalSpeeds& critical,
                                     const core::MillSpeedUncertainty& uncertainty,
                                     double confidence,
                                     const std::vector<std::optional<Posterior>>& posteriors) {
    return tandem_uncertainty_detail::uncertainty_table().write(
        {critical, uncertainty, confidence, posteriors});
}

std::vector<ResultSchema> mill_uncertainty_schemas() {
    return {result_schema(tandem_uncertainty_detail::uncertainty_row_table()),
            result_schema(tandem_uncertainty_detail::uncertainty_table())};
}

}  // namespace rollgap::api
