#include "service/chunked.h"

#include <map>
#include <string>
#include <variant>

#include "api/field_errors.h"
#include "api/problem.h"
#include "api/result_table.h"
#include "api/text.h"
#include "service/analyses/table.h"

namespace rollgap::service {
namespace {

Outcome invalid_points(std::string detail) {
    return problem_outcome(api::make_problem(api::ProblemCode::invalid_request, std::move(detail)));
}

Outcome not_pointwise(const PreparedRequest& ready) {
    return invalid_points(api::concat("the analysis '", ready.analysis->name,
                                      "' does not split into points: evaluate it whole"));
}

}  // namespace

std::optional<std::int64_t> chunkable_points(const nlohmann::json& request) {
    try {
        auto prepared = prepare_request(request, analyses());
        const auto* ready = std::get_if<PreparedRequest>(&prepared);
        if (ready == nullptr || !ready->prepared.points) return std::nullopt;
        return ready->prepared.points->count;
    } catch (...) {
        // evaluate() reports the same exception as the problem `internal` when the job runs.
        return std::nullopt;
    }
}

Outcome evaluate_points(const nlohmann::json& request, std::int64_t begin, std::int64_t end,
                        const core::Control& control) {
    return guarded([&] {
        auto prepared = prepare_request(request, analyses());
        if (auto* problem = std::get_if<Outcome>(&prepared)) return std::move(*problem);
        const PreparedRequest& ready = std::get<PreparedRequest>(prepared);
        if (!ready.prepared.points) return not_pointwise(ready);
        const PointwiseRun& points = *ready.prepared.points;
        if (begin < 0 || begin > end || end > points.count) {
            return invalid_points(api::concat(
                "points [", std::to_string(begin), ", ", std::to_string(end),
                ") are not a range of this request's points [0, ", std::to_string(points.count),
                "): give 0 <= begin <= end <= ", std::to_string(points.count)));
        }
        if (control.should_stop()) return cancelled_outcome();
        Outcome outcome;
        try {
            outcome.body =
                begin == end ? nlohmann::json::array() : points.compute(begin, end, control);
        } catch (const AnalysisCancelled&) {
            return cancelled_outcome();
        }
        control.report(1.0);
        return outcome;
    });
}

Outcome assemble_points(const nlohmann::json& request, const nlohmann::json& points) {
    return guarded([&] {
        auto prepared = prepare_request(request, analyses());
        if (auto* problem = std::get_if<Outcome>(&prepared)) return std::move(*problem);
        PreparedRequest& ready = std::get<PreparedRequest>(prepared);
        if (!ready.prepared.points) return not_pointwise(ready);
        const std::int64_t count = ready.prepared.points->count;
        if (!points.is_array() || static_cast<std::int64_t>(points.size()) != count) {
            return invalid_points(
                api::concat("the points to assemble must be an array of this request's ",
                            std::to_string(count), " point documents, got ",
                            points.is_array() ? api::concat(std::to_string(points.size()), " items")
                                              : std::string(api::json_type_name(points))));
        }
        for (std::size_t i = 0; i < points.size(); ++i) {
            if (!points[i].is_object()) {
                return invalid_points(api::concat("point ", std::to_string(i),
                                                  " to assemble is not a point document (",
                                                  api::json_type_name(points[i]), ")"));
            }
        }
        nlohmann::json result = ready.prepared.points->assemble(points);
        return result_outcome(ready, std::move(result));
    });
}

nlohmann::json partial_result(
    std::int64_t points_total,
    const std::vector<std::pair<std::int64_t, nlohmann::json>>& finished_chunks) {
    // Index order whatever order the chunks finished in; a point held twice is listed once.
    std::map<std::int64_t, const nlohmann::json*> by_index;
    for (const auto& [begin, documents] : finished_chunks) {
        if (!documents.is_array()) continue;
        for (std::size_t k = 0; k < documents.size(); ++k) {
            const std::int64_t index = begin + static_cast<std::int64_t>(k);
            if (index >= 0 && index < points_total) by_index.try_emplace(index, &documents[k]);
        }
    }
    nlohmann::json points = nlohmann::json::array();
    for (const auto& [index, document] : by_index)
        points.push_back({{"index", index}, {"point", *document}});
    return {
        {"partial", true},
        {"points_total", points_total},
        {"points_done", static_cast<std::int64_t>(by_index.size())},
        {"points", std::move(points)},
    };
}

nlohmann::json partial_result_schema(std::span<const Analysis> offered) {
    nlohmann::json partial = api::boolean_schema();
    partial["const"] = true;
    partial["description"] =
        "Always true: the job is still running and this lists only the points finished so far.";
    nlohmann::json total = api::integer_schema();
    total["minimum"] = 0;
    total["description"] = "The points of the whole analysis (a sweep's values, a map's cells).";
    nlohmann::json done = api::integer_schema();
    done["minimum"] = 0;
    done["description"] = "The points finished so far (the length of points).";
    nlohmann::json index = api::integer_schema();
    index["minimum"] = 0;
    index["description"] =
        "The point's index in the final result's points (sweep) or cells (map, row-major).";
    nlohmann::json kinds = nlohmann::json::array();
    for (const Analysis& analysis : offered) {
        for (const std::string_view component : analysis.point_components)
            kinds.push_back(api::ref_schema(component));
    }
    nlohmann::json point = {
        {"oneOf", std::move(kinds)},
        {"description", "The point's entry exactly as the final result will list it."},
    };
    nlohmann::json entry = api::object_schema(
        "A finished point.", {{"index", index}, {"point", point}}, {"index", "point"});
    nlohmann::json points = api::array_schema(std::move(entry));
    points["description"] = "The finished points in index order, each once.";
    return api::object_schema(
        "The points a sweep or map has finished: while it runs, and kept when it is cancelled "
        "or fails; the complete result replaces it when the job succeeds.",
        {{"partial", partial}, {"points_total", total}, {"points_done", done}, {"points", points}},
        {"partial", "points_total", "points_done", "points"});
}

}  // namespace rollgap::service
