// The analysis descriptor (service/analyses/analysis.h) walked row by row: every analysis is
// reachable everywhere the service names analyses — its HTTP route, the OpenAPI document (its
// path, its answer, options and result components, the job answer's discriminator), CSV (if it
// has tables), chunked jobs (if it is pointwise) and the document's analysis list, which the
// workbench page is built from. A row added without its files fails here, by name.

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <initializer_list>
#include <fstream>
#include <sstream>
#include <string>
#include <variant>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "service/analyses/table.h"
#include "service/chunked.h"
#include "service/evaluate.h"
#include "service/http/routes.h"
#include "service/openapi.h"
#include "support/repository.h"

using nlohmann::json;
using namespace rollgap;

namespace {

bool has_component(const json& document, std::string_view name) {
    return document["components"]["schemas"].contains(std::string(name));
}

// The request of the analysis' row prepared with the first minimal options of its row.
service::PreparedAnalysis prepare_minimal(const service::Analysis& analysis) {
    api::FieldErrors errors;
    if (analysis.subject() == service::Subject::batch) {
        // A batch has no defaults of its own: the least batch is one item of a cheap analysis.
        service::PreparedAnalysis prepared = analysis.prepare_batch(
            json::parse(R"({"analysis": "roll_gap", "items": [{"label": "coil-1"}]})"), "/options",
            errors);
        CHECK_MESSAGE(errors.empty(), analysis.name, ": its minimal options are refused");
        return prepared;
    }
    REQUIRE(!analysis.options_defaults.empty());
    const json options = json::parse(analysis.options_defaults.front().minimal_options);
    service::PreparedAnalysis prepared =
        analysis.subject() == service::Subject::mill
            ? analysis.prepare_mill(core::default_mill(), options, "/options", errors)
            : analysis.prepare(core::Scenario{}, options, "/options", errors);
    CHECK_MESSAGE(errors.empty(), analysis.name, ": its minimal options are refused");
    return prepared;
}

}  // namespace

TEST_CASE("every analysis of the descriptor has its route, and each analysis route a row") {
    for (const service::Analysis& analysis : service::analyses()) {
        CAPTURE(analysis.name);
        const service::http::Route* route = service::http::match_route(analysis.path);
        REQUIRE(route != nullptr);
        CHECK(route->id == service::http::RouteId::analysis);
        CHECK(route->analysis == analysis.name);
        CHECK(service::http::method_allowed(*route, "POST"));
        CHECK(route->compute);
    }
    for (const service::http::Route& route : service::http::all_routes()) {
        if (route.id != service::http::RouteId::analysis) continue;
        CAPTURE(route.pattern);
        CHECK(service::find_analysis(service::analyses(), route.analysis) != nullptr);
    }
}

TEST_CASE("every analysis is in the OpenAPI document: path, answer, options, result") {
    const json document = service::openapi_document();
    const json& schemas = document["components"]["schemas"];
    const json& enum_names = schemas["AnalysisRequest"]["properties"]["analysis"]["enum"];
    const json& mapping = schemas["AnalysisResponse"]["discriminator"]["mapping"];
    for (const service::Analysis& analysis : service::analyses()) {
        CAPTURE(analysis.name);
        const std::string path(analysis.path);
        REQUIRE(document["paths"].contains(path));
        const json& post = document["paths"][path]["post"];
        CHECK(post.contains("requestBody"));
        if (analysis.subject() == service::Subject::batch) {
            // Its route queues a job (202, or 200 for a retried Idempotency-Key); the answer
            // is that job's result.
            CHECK(post["responses"]["202"]["content"]["application/json"]["schema"]["$ref"] ==
                  "#/components/schemas/Job");
        } else {
            CHECK(post["responses"]["200"]["content"]["application/json"]["schema"]["$ref"] ==
                  test::joined({"#/components/schemas/", analysis.response_schema}));
        }
        CHECK(has_component(document, analysis.response_schema));
        CHECK(has_component(document, analysis.options_schema));
        CHECK(has_component(document, analysis.result_schema));
        for (const service::OptionsDefaults& entry : analysis.options_defaults)
            CHECK(has_component(document, entry.schema));
        CHECK(std::find(enum_names.begin(), enum_names.end(), json(analysis.name)) !=
              enum_names.end());
        CHECK(mapping.contains(std::string(analysis.name)));
        // The request a job takes names the analysis' options component too.
        CHECK(document.dump().find(test::joined({"\"#/components/schemas/", analysis.options_schema,
                                                 "\""})) != std::string::npos);
    }
}

TEST_CASE("an analysis with CSV tables offers them in OpenAPI and answers them") {
    const json document = service::openapi_document();
    for (const service::Analysis& analysis : service::analyses()) {
        CAPTURE(analysis.name);
        // A batch's result is a job's: GET /v1/jobs/{id} offers its tables.
        const json& operation = analysis.subject() == service::Subject::batch
                                    ? document["paths"]["/v1/jobs/{id}"]["get"]
                                    : document["paths"][std::string(analysis.path)]["post"];
        const bool offers_csv = operation["responses"]["200"]["content"].contains("text/csv");
        if (analysis.subject() == service::Subject::batch) CHECK(offers_csv);
        else CHECK(offers_csv == !analysis.tables().empty());
        for (const api::CsvTable& table : analysis.tables()) {
            CAPTURE(table.name);
            bool listed = false;
            for (const json& parameter : operation["parameters"]) {
                if (parameter.value("name", "") != "table") continue;
                const json& names = parameter["schema"]["enum"];
                listed = std::find(names.begin(), names.end(), json(table.name)) != names.end();
            }
            CHECK(listed);
        }
    }
}

TEST_CASE("a pointwise analysis splits into points and its points are in the partial schema") {
    const json partial = service::partial_result_schema();
    const std::string points = partial.dump();
    const json document = service::openapi_document();
    for (const service::Analysis& analysis : service::analyses()) {
        CAPTURE(analysis.name);
        const service::PreparedAnalysis prepared = prepare_minimal(analysis);
        CHECK(prepared.points.has_value() == analysis.pointwise());
        for (const std::string_view component : analysis.point_components) {
            CAPTURE(component);
            CHECK(has_component(document, component));
            CHECK(points.find(test::joined({"\"#/components/schemas/", component, "\""})) !=
                  std::string::npos);
        }
    }
}

TEST_CASE("the document's analysis list (x-rollgap-analyses) is the rows, in order") {
    // What the workbench page builds its selector and CSV download from.
    const json document = service::openapi_document();
    REQUIRE(document.contains("x-rollgap-analyses"));
    const json& listed = document["x-rollgap-analyses"];
    REQUIRE(listed.is_array());
    const auto rows = service::analyses();
    REQUIRE(listed.size() == rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const service::Analysis& analysis = rows[i];
        const json& entry = listed[i];
        CAPTURE(analysis.name);
        CHECK(entry.size() == 9);
        CHECK(entry.value("name", "") == analysis.name);
        // the options component with the defaults, which the page's options form shows
        CHECK(entry.value("options_schema", "") == analysis.options_schema);
        CHECK(document["components"]["schemas"][std::string(analysis.options_schema)].is_object());
        CHECK(entry.value("label", "") == analysis.label);
        CHECK(!analysis.label.empty());
        CHECK(entry.value("summary", "") == analysis.summary);
        CHECK(entry.value("path", "") == analysis.path);
        CHECK(document["paths"].contains(entry.value("path", "")));
        CHECK(entry["csv"] == !analysis.tables().empty());
        // csv says whether the route answers text/csv, as the operation in the document says.
        const json& ok =
            analysis.subject() == service::Subject::batch
                ? document["paths"]["/v1/jobs/{id}"]["get"]["responses"]["200"]
                : document["paths"][std::string(analysis.path)]["post"]["responses"]["200"];
        CHECK(entry["csv"] == ok["content"].contains("text/csv"));
        CHECK(entry["pointwise"] == analysis.pointwise());
        CHECK(entry["on_page"] == analysis.on_page);
    }
}
