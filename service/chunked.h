#pragma once
// A sweep or a map as a job split into chunks of points that workers on any replica compute
// (docs/job-store.md): which requests split and into how many points, a chunk's points, the
// result assembled from all chunks, and the partial result a running job shows.
//
// The analyses run their own single-process evaluate() through the same two steps
// (service/analyses/analysis.h, PointwiseRun): points written one document each, then the result
// assembled from the documents, with everything that depends on neighbours (chatter-type
// changes) derived from them. So assemble_points of all chunks is evaluate()'s answer by
// construction, not by a second writer kept in step with the first.
//
// Point documents are JSON that the store may keep as text: numbers survive dump and parse
// exactly (nlohmann writes doubles in round-trip precision), so the assembled answer is
// byte-identical to evaluate()'s whether the chunks come from memory or from the database.

#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/control.h"
#include "service/analyses/analysis.h"
#include "service/analyses/table.h"
#include "service/evaluate.h"

namespace rollgap::service {

// How many independent points a valid request's analysis splits into: a sweep its values, a map
// rows × columns cells (row-major index). Nothing for every other analysis, and for a request
// evaluate() would refuse (it runs whole and fails as evaluate() says). Validates the request,
// so it costs what prepare() costs (milliseconds for the largest map), never a computation.
std::optional<std::int64_t> chunkable_points(const nlohmann::json& request);

// The documents of points [begin, end) of a chunkable request, computed: an Outcome whose body is
// a JSON array of exactly end − begin documents, each the entry the final result lists for the
// point (a sweep's points[i], a map's cells[i]). Problems as evaluate() gives them (the
// request's validation, `cancelled` when `control` stops the chunk, `internal`); a request that
// does not split, or a range outside [0, chunkable_points], is the problem invalid_request.
// `control` passes through: its cancellation stops the chunk within one point, its progress
// goes 0..1 over this chunk's points.
Outcome evaluate_points(const nlohmann::json& request, std::int64_t begin, std::int64_t end,
                        const core::Control& control = {});

// From the documents of all points concatenated in index order: exactly the Outcome
// evaluate(request) gives (its body dumps byte-identical), including the chatter-type changes
// between neighbours. Points that are not one JSON object per point of the request are the
// problem invalid_request.
Outcome assemble_points(const nlohmann::json& request, const nlohmann::json& points);

// The partial result of a running chunked job: {"partial": true, "points_total", "points_done",
// "points": [{"index", "point"}]} from the finished chunks (the index of each chunk's first
// point and its JSON array of documents), in index order. A point that two chunks hold (a chunk
// re-run after its lease expired) is listed once; non-array chunks and points outside
// [0, points_total) are skipped.
nlohmann::json partial_result(
    std::int64_t points_total,
    const std::vector<std::pair<std::int64_t, nlohmann::json>>& finished_chunks);

// The OpenAPI schema (JSON Schema 2020-12) of partial_result's document; "point" is one of the
// point components of the pointwise analyses of `offered` (Analysis::point_components: a
// sweep's SweepCriticalSpeedPoint and SweepAmplitudePoint, a map's MapCell) that the result
// tables already define, referenced as #/components/schemas/<name>.
nlohmann::json partial_result_schema(std::span<const Analysis> offered = analyses());

}  // namespace rollgap::service
