#pragma once
// CSV instead of JSON, on request: Accept: text/csv on an analysis route or a finished job
// (GET /v1/jobs/{id}), `rollgap run --format csv`. The tables and the format are api/csv.h's.

#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "api/csv.h"

namespace rollgap::service {

// RFC 4180 with its header parameter (RFC 7111 / 4180 §3): the first record names the columns.
inline constexpr std::string_view csv_content_type = "text/csv; charset=utf-8; header=present";

// Whether an Accept header prefers CSV: text/csv listed with q > 0 and at least the quality
// application/json gets (itself, application/*, or */*). Without an Accept header: JSON.
bool wants_csv(std::string_view accept);

// The quality (0 to 1) an Accept header gives a media type: that of the most specific range
// matching it (the type itself, type/*, */*), -1 when none does.
double accept_quality(std::string_view accept, std::string_view type);

struct CsvAnswer {
    int status = 200;  // 200, or 406 with a problem
    std::string body;
    std::string_view media_type;
};

// `answer`: what an analysis answers ({"analysis", "scenario", "options", "result"}) or a job
// document (its "result" once it succeeded). `table` "" is the analysis' first table.
// `units`: "si" or "" (the JSON's units) or "plant" (m/min, mPa·s: api/csv.h CsvUnits); any
// other value is the caller's to refuse (parse_csv_units).
CsvAnswer csv_answer(const nlohmann::json& answer, std::string_view table,
                     std::string_view units = "");

// The units=… of a request: nothing when it is neither "si" nor "plant" ("" is si).
std::optional<api::CsvUnits> parse_csv_units(std::string_view units);

}  // namespace rollgap::service
