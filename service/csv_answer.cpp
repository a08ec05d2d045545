#include "service/csv_answer.h"

#include <algorithm>
#include <cctype>
#include <charconv>

#include "api/csv.h"
#include "api/problem.h"
#include "api/text.h"
#include "service/analyses/table.h"

namespace rollgap::service {
namespace {

std::string_view trim(std::string_view text) {
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front())) != 0)
        text.remove_prefix(1);
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back())) != 0)
        text.remove_suffix(1);
    return text;
}

std::string lower(std::string_view text) {
    std::string out(text);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

// The quality an Accept header gives a media type (the most specific range that matches), or -1.
double quality(std::string_view accept, std::string_view type) {
    const std::string_view major = type.substr(0, type.find('/'));
    double best = -1.0;
    int best_specificity = -1;
    while (!accept.empty()) {
        const std::size_t comma = accept.find(',');
        std::string_view item = accept.substr(0, comma);
        accept = comma == std::string_view::npos ? std::string_view() : accept.substr(comma + 1);
        const std::size_t semicolon = item.find(';');
        const std::string range = lower(trim(item.substr(0, semicolon)));
        double q = 1.0;
        for (std::string_view parameters =
                 semicolon == std::string_view::npos ? "" : item.substr(semicolon + 1);
             !parameters.empty();) {
            const std::size_t next = parameters.find(';');
            const std::string_view parameter = trim(parameters.substr(0, next));
            parameters =
                next == std::string_view::npos ? std::string_view() : parameters.substr(next + 1);
            if (parameter.size() > 2 && (parameter[0] == 'q' || parameter[0] == 'Q') &&
                parameter[1] == '=') {
                const std::string_view value = parameter.substr(2);
                double parsed = 0.0;
                if (std::from_chars(value.data(), value.data() + value.size(), parsed).ec ==
                    std::errc())
                    q = parsed;
            }
        }
        const int specificity = range == type                       ? 2
                                : range == api::concat(major, "/*") ? 1
                                : range == "*/*"                    ? 0
                                                                    : -1;
        if (specificity > best_specificity) {
            best_specificity = specificity;
            best = q;
        }
    }
    return best;
}

CsvAnswer not_acceptable(std::string detail) {
    const api::Problem problem =
        api::make_problem(api::ProblemCode::not_acceptable, std::move(detail));
    return {
        problem.http_status(),
        api::problem_json(problem).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
        api::problem_media_type};
}

// Why an analysis' result has no CSV, naming those that have (the rows with tables).
std::string no_tables(std::string_view analysis) {
    std::string with_tables;
    for (const Analysis& row : analyses()) {
        if (!row.tables().empty())
            with_tables += api::concat(with_tables.empty() ? "" : ", ", row.name);
    }
    return api::concat("the ", analysis,
                       " result has no table to give as CSV: ask for application/json, or run the "
                       "analysis whose table you want (",
                       with_tables, ")");
}

}  // namespace

double accept_quality(std::string_view accept, std::string_view type) {
    return quality(accept, type);
}

bool wants_csv(std::string_view accept) {
    const double csv = quality(accept, "text/csv");
    if (csv <= 0.0) return false;
    // Only an explicit text/csv counts: */* alone is the default of every client.
    if (lower(accept).find("text/csv") == std::string::npos) return false;
    return csv >= quality(accept, "application/json");
}

std::optional<api::CsvUnits> parse_csv_units(std::string_view units) {
    if (units.empty() || units == "si") return api::CsvUnits::si;
    if (units == "plant") return api::CsvUnits::plant;
    return std::nullopt;
}

CsvAnswer csv_answer(const nlohmann::json& answer, std::string_view table, std::string_view units) {
    const nlohmann::json* response = &answer;
    if (answer.contains("state")) {  // a job document
        const std::string state = answer.value("state", std::string());
        if (!answer.contains("result")) {
            return not_acceptable(
                api::concat("job ", answer.value("id", std::string()), " is ", state,
                            ": only a succeeded job has a result to give as CSV"));
        }
        response = &answer.at("result");
    }
    const std::string analysis = response->value("analysis", std::string());
    const Analysis* row = find_analysis(analyses(), analysis);
    if (row == nullptr || row->tables().empty()) return not_acceptable(no_tables(analysis));
    const api::CsvOutcome csv =
        api::result_csv(row->tables(), analysis, response->value("result", nlohmann::json()), table,
                        parse_csv_units(units).value_or(api::CsvUnits::si));
    if (!csv.ok) return not_acceptable(csv.detail);
    return {200, csv.text, csv_content_type};
}

}  // namespace rollgap::service
