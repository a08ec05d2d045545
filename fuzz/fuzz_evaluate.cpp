// libFuzzer harness: the request facade, JSON text in, a result or a problem out — what the CLI
// (`rollgap run`) and every HTTP analysis route do with a body. Any text must give a complete
// answer: never a crash, an exception, an internal error (500 means an exception escaped an
// analysis) or a number JSON cannot carry (nlohmann writes NaN as null, silently).
//
// The work per input is bounded without touching the product's limits: the Control cancels the
// analysis after a fixed number of polls (deterministic, unlike a clock), so a valid request for
// a long sweep ends as the problem `cancelled` like a request past its deadline does.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "api/problem.h"
#include "core/control.h"
#include "fuzz/fuzz_input.h"
#include "service/evaluate.h"

using namespace rollgap;
using fuzz::require;
using nlohmann::json;

namespace {

// Units of work (scan speeds, sweep points, output times) one input may use.
constexpr int poll_budget = 64;

bool all_numbers_finite(const json& value) {
    switch (value.type()) {
        case json::value_t::number_float: return std::isfinite(value.get<double>());
        case json::value_t::object:
        case json::value_t::array:
            for (const json& item : value) {
                if (!all_numbers_finite(item)) return false;
            }
            return true;
        default: return true;
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    spdlog::set_level(spdlog::level::off);  // an internal error aborts below anyway
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    int polls = 0;
    core::Control control;
    control.cancelled = [&polls] { return ++polls > poll_budget; };
    control.threads = 1;

    const service::Outcome outcome = service::evaluate_text(text, control);

    require(outcome.body.is_object(), "the body is a JSON object");
    require(all_numbers_finite(outcome.body), "every number in the body is finite");
    // The HTTP layer and the CLI write bodies this way: a parser message may quote the client's
    // invalid UTF-8, which becomes U+FFFD on the way out.
    try {
        (void)outcome.body.dump(-1, ' ', false, json::error_handler_t::replace);
    } catch (const json::exception&) {
        require(false, "the body serialises");
    }
    if (outcome.ok()) {
        require(outcome.http_status == 200, "a result is 200");
        // a stand's analysis echoes its scenario, a mill's (tandem) its mill, never both; a
        // batch neither (its items are in its options)
        const bool batch = outcome.body.value("analysis", "") == "batch";
        require(
            outcome.body.contains("result") &&
                (batch ? !outcome.body.contains("scenario") && !outcome.body.contains("tandem")
                       : outcome.body.contains("scenario") != outcome.body.contains("tandem")) &&
                outcome.body.contains("options") && outcome.body.contains("analysis"),
            "a result echoes analysis, its scenario or mill (a batch neither), and options");
        return 0;
    }
    require(*outcome.problem != api::ProblemCode::internal,
            "no internal error (an exception escaped)");
    require(outcome.http_status >= 400 && outcome.http_status <= 599, "a problem is 4xx or 5xx");
    require(outcome.body.value("status", 0) == outcome.http_status,
            "the problem's status is the HTTP status");
    require(outcome.body.contains("type") && outcome.body.contains("title"),
            "a problem has type and title");
    return 0;
}
