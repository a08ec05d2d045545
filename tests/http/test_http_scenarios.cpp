// Stored stand scenarios over HTTP (PUT/GET/DELETE /v1/scenarios/{name}, GET /v1/scenarios) and
// requests with "base": a real server in process on a fresh SQLite store of its own.

#include <doctest/doctest.h>

#include <stdlib.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "api/request_json.h"
#include "service/cli.h"
#include "service/evaluate.h"
#include "service/openapi.h"
#include "service/http/serve_main.h"
#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;

namespace {

// A directory of its own under /tmp, removed at the end.
struct TempDir {
    std::filesystem::path path;
    TempDir() {
        std::string pattern =
            (std::filesystem::temp_directory_path() / "rollgap-scenarios-XXXXXX").string();
        REQUIRE(::mkdtemp(pattern.data()) != nullptr);
        path = pattern;
    }
    ~TempDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
};

service::ServerConfig config_with_store(const std::string& store) {
    service::ServerConfig config = test_config();
    config.store = store;
    return config;
}

httplib::Result put_scenario(httplib::Client& client, const std::string& name, const json& body,
                             const httplib::Headers& headers = {}) {
    return client.Put(("/v1/scenarios/" + name).c_str(), headers, body.dump(), "application/json");
}

// A stand that differs from the default where it changes the roll bite.
const json stand_patch = {{"strip", {{"reduction", 0.25}, {"entry_thickness_mm", 2.0}}},
                          {"rolls", {{"speed_m_per_s", 12.0}}}};

}  // namespace

TEST_CASE("scenarios over http: create, read, list, replace with If-Match, delete") {
    TempDir dir;
    TestServer server(config_with_store("sqlite:" + (dir.path / "jobs.db").string()));
    auto client = server.client();

    // Nothing stored yet.
    CHECK(body_json(client.Get("/v1/scenarios")) == json{{"scenarios", json::array()}});
    CHECK(client.Get("/v1/scenarios/stand-3")->status == 404);

    auto created = put_scenario(client, "stand-3", stand_patch);
    REQUIRE(created);
    CHECK(created->status == 201);
    CHECK(created->get_header_value("ETag") == "\"1\"");
    CHECK(created->get_header_value("Location") == "/v1/scenarios/stand-3");
    // The resolved full scenario is stored: the default with the patch applied, every field.
    json expected = body_json(client.Get("/v1/scenarios/default"));
    expected.merge_patch(stand_patch);
    CHECK(body_json(created) == expected);

    auto read = client.Get("/v1/scenarios/stand-3");
    REQUIRE(read);
    CHECK(read->status == 200);
    CHECK(read->get_header_value("ETag") == "\"1\"");
    CHECK(body_json(read) == expected);

    // Replacing without If-Match: 428, and nothing changes.
    const json faster = {{"rolls", {{"speed_m_per_s", 14.0}}}};
    auto unconditional = put_scenario(client, "stand-3", faster);
    REQUIRE(unconditional);
    CHECK(unconditional->status == 428);
    CHECK(body_json(unconditional)["code"] == "precondition_required");
    // Create-only on an existing name: 412.
    CHECK(put_scenario(client, "stand-3", faster, {{"If-None-Match", "*"}})->status == 412);
    // A stale version: 412.
    CHECK(put_scenario(client, "stand-3", faster, {{"If-Match", "\"7\""}})->status == 412);
    CHECK(body_json(client.Get("/v1/scenarios/stand-3")) == expected);

    // The version the editor read: replaced, new ETag. The body is again a patch onto the
    // default (not onto the stored version): a full replacement.
    auto replaced = put_scenario(client, "stand-3", faster, {{"If-Match", "\"1\""}});
    REQUIRE(replaced);
    CHECK(replaced->status == 200);
    CHECK(replaced->get_header_value("ETag") == "\"2\"");
    json expected_replaced = body_json(client.Get("/v1/scenarios/default"));
    expected_replaced.merge_patch(faster);
    CHECK(body_json(client.Get("/v1/scenarios/stand-3")) == expected_replaced);
    // The editor who still holds version 1 cannot overwrite that.
    CHECK(put_scenario(client, "stand-3", stand_patch, {{"If-Match", "\"1\""}})->status == 412);
    // If-Match: * replaces whatever version is current; on a missing name it fails.
    CHECK(put_scenario(client, "stand-3", faster, {{"If-Match", "*"}})->status == 200);
    CHECK(put_scenario(client, "nowhere", faster, {{"If-Match", "*"}})->status == 412);
    CHECK(client.Get("/v1/scenarios/nowhere")->status == 404);

    // If-None-Match: * creates.
    CHECK(put_scenario(client, "A.line_2", json::object(), {{"If-None-Match", "*"}})->status ==
          201);
    const json listed = body_json(client.Get("/v1/scenarios"));
    REQUIRE(listed["scenarios"].size() == 2);
    CHECK(listed["scenarios"][0]["name"] == "A.line_2");  // by name (ASCII order)
    CHECK(listed["scenarios"][0]["version"] == 1);
    CHECK(listed["scenarios"][1]["name"] == "stand-3");
    CHECK(listed["scenarios"][1]["version"] == 3);
    const std::string updated = listed["scenarios"][1]["updated_at"];
    CHECK(updated.size() == 24);  // 2026-12-01T05:12:57.123Z
    CHECK(updated.back() == 'Z');

    // DELETE: a stale If-Match is refused, the current one (or none) deletes.
    CHECK(client.Delete("/v1/scenarios/stand-3", {{"If-Match", "\"2\""}})->status == 412);
    CHECK(client.Delete("/v1/scenarios/stand-3", {{"If-Match", "\"3\""}})->status == 204);
    CHECK(client.Get("/v1/scenarios/stand-3")->status == 404);
    CHECK(client.Delete("/v1/scenarios/stand-3")->status == 404);
    // A list of tags and "*" are compared with the current version.
    CHECK(put_scenario(client, "A.line_2", faster, {{"If-None-Match", "W/\"1\", \"5\""}})->status ==
          412);
    CHECK(
        put_scenario(client, "A.line_2", json::object(), {{"If-Match", "\"5\", \"1\""}})->status ==
        200);
    CHECK(client.Delete("/v1/scenarios/A.line_2", {{"If-Match", "\"1\""}})->status == 412);
    CHECK(client.Delete("/v1/scenarios/A.line_2", {{"If-Match", "*"}})->status == 204);
    CHECK(body_json(client.Get("/v1/scenarios")) == json{{"scenarios", json::array()}});

    // One log line per request, with the route template as its label.
    CHECK(server.log_text().find("route=/v1/scenarios/{name}") != std::string::npos);
    CHECK(server.log_text().find("route=/v1/scenarios ") != std::string::npos);
}

TEST_CASE("scenarios over http: validated on write, names checked, default reserved") {
    TempDir dir;
    TestServer server(config_with_store("sqlite:" + (dir.path / "jobs.db").string()));
    auto client = server.client();

    SUBCASE("a scenario outside its bounds: 422 naming the field, its bound and unit") {
        auto refused =
            put_scenario(client, "stand-3",
                         {{"strip", {{"reduction", 25}}}, {"rolls", {{"speed_m_per_sec", 12}}}});
        REQUIRE(refused);
        CHECK(refused->status == 422);
        CHECK(refused->get_header_value("Content-Type") == "application/problem+json");
        const json problem = body_json(refused);
        CHECK(problem["code"] == "invalid_scenario");
        std::vector<std::string> pointers;
        for (const json& error : problem["errors"]) pointers.push_back(error["pointer"]);
        CHECK(pointers == std::vector<std::string>{"/strip/reduction", "/rolls/speed_m_per_sec"});
        CHECK(problem["errors"][0]["bound"] == "(0, 0.7]");
        CHECK(problem["errors"][0]["unit"] == "1");
        // Nothing was stored.
        CHECK(client.Get("/v1/scenarios/stand-3")->status == 404);
    }
    SUBCASE("a cross-field rule on the merged scenario: the same check as the analyses") {
        const json tension = {{"tension", {{"back", {{"stress_MPa", 400}}}}}};
        const json analysis = body_json(post_json(client, "/v1/roll-gap", {{"scenario", tension}}));
        const json stored = body_json(put_scenario(client, "stand-3", tension));
        REQUIRE(analysis["status"] == 422);
        CHECK(stored["status"] == 422);
        CHECK(stored["errors"][0]["pointer"] == "/tension/back/stress_MPa");
        CHECK(analysis["errors"][0]["pointer"] == "/scenario/tension/back/stress_MPa");
        CHECK(stored["errors"][0]["bound"] == analysis["errors"][0]["bound"]);
    }
    SUBCASE("a body that is not an object, not JSON, not application/json") {
        CHECK(client.Put("/v1/scenarios/stand-3", "[1]", "application/json")->status == 422);
        CHECK(client.Put("/v1/scenarios/stand-3", "{", "application/json")->status == 400);
        CHECK(client.Put("/v1/scenarios/stand-3", "{}", "text/plain")->status == 415);
        CHECK(client.Get("/v1/scenarios/stand-3")->status == 404);
    }
    SUBCASE("names: the pattern is the bound; default is reserved") {
        for (const std::string& name : std::vector<std::string>{
                 "-leading-dash", ".hidden", "has%20space", std::string(65, 'a')}) {
            CAPTURE(name);
            auto refused = put_scenario(client, name, json::object());
            REQUIRE(refused);
            CHECK(refused->status == 422);
            CHECK(body_json(refused)["errors"][0]["bound"] == "^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$");
            CHECK(client.Get(("/v1/scenarios/" + name).c_str())->status == 422);
        }
        CHECK(put_scenario(client, std::string(64, 'a'), json::object())->status == 201);
        auto put_default = put_scenario(client, "default", json::object());
        REQUIRE(put_default);
        CHECK(put_default->status == 422);
        CHECK(body_json(put_default)["detail"].get<std::string>().find("'default'") !=
              std::string::npos);
        CHECK(client.Delete("/v1/scenarios/default")->status == 422);
        // The built-in default is still served from code.
        CHECK(client.Get("/v1/scenarios/default")->status == 200);
        CHECK(client.Options("/v1/scenarios/stand-3")->get_header_value("Allow") ==
              "GET, HEAD, PUT, PATCH, DELETE, OPTIONS");
    }
    SUBCASE("a body over the size limit is refused before it is read") {
        const std::string answer = raw_exchange(
            server.port(),
            "PUT /v1/scenarios/stand-3 HTTP/1.1\r\nHost: t\r\nContent-Type: application/json\r\n"
            "Content-Length: 2000000\r\n\r\n{");
        CHECK(answer.starts_with("HTTP/1.1 413"));
        CHECK(client.Get("/v1/scenarios/stand-3")->status == 404);
    }
}

TEST_CASE("scenarios over http: the bearer token rule of the job endpoints") {
    TempDir dir;
    service::ServerConfig config = config_with_store("sqlite:" + (dir.path / "jobs.db").string());
    config.token = "s3cret";
    TestServer server(config);
    auto client = server.client();
    CHECK(put_scenario(client, "stand-3", json::object())->status == 401);
    CHECK(client.Get("/v1/scenarios")->status == 401);
    CHECK(client.Get("/v1/scenarios/stand-3")->status == 401);
    CHECK(client.Get("/v1/scenarios/default")->status == 200);  // never needs it
    const httplib::Headers bearer = {{"Authorization", "Bearer s3cret"}};
    CHECK(put_scenario(client, "stand-3", json::object(), bearer)->status == 201);
    CHECK(client.Get("/v1/scenarios/stand-3", bearer)->status == 200);
}

TEST_CASE("scenarios over http: a request with base computes its patch on the stored stand") {
    TempDir dir;
    TestServer server(config_with_store("sqlite:" + (dir.path / "jobs.db").string()));
    auto client = server.client();
    REQUIRE(put_scenario(client, "stand-3", stand_patch)->status == 201);
    REQUIRE(put_scenario(client, "stand-3", stand_patch, {{"If-Match", "\"1\""}})->status == 200);

    // On top of the stored stand: a lubricant change, and null restoring the built-in
    // default speed (null means the default, not the stored value).
    const json patch = {{"lubricant", {{"viscosity_Pa_s", 0.0008}}},
                        {"rolls", {{"speed_m_per_s", nullptr}}}};
    const json options = {{"distributions", false}};
    const json with_base = body_json(post_json(
        client, "/v1/roll-gap", {{"base", "stand-3"}, {"scenario", patch}, {"options", options}}));
    // The same stand written out by hand as a patch onto the default.
    const json by_hand = {{"strip", {{"reduction", 0.25}, {"entry_thickness_mm", 2.0}}},
                          {"lubricant", {{"viscosity_Pa_s", 0.0008}}}};
    const json without_base =
        body_json(post_json(client, "/v1/roll-gap", {{"scenario", by_hand}, {"options", options}}));
    REQUIRE(with_base.contains("result"));
    CHECK(with_base["result"] == without_base["result"]);
    CHECK(with_base["scenario"] == without_base["scenario"]);
    CHECK(with_base["base"] == json{{"name", "stand-3"}, {"version", 2}});
    CHECK_FALSE(without_base.contains("base"));
    // The base mattered: the default stand gives another force.
    const json plain =
        body_json(post_json(client, "/v1/roll-gap", {{"scenario", patch}, {"options", options}}));
    CHECK(plain["result"]["force_kN"] != with_base["result"]["force_kN"]);

    SUBCASE("validation points into the request, also for the stored fields") {
        const json refused = body_json(
            post_json(client, "/v1/roll-gap",
                      {{"base", "stand-3"}, {"scenario", {{"strip", {{"reduction", 0.9}}}}}}));
        CHECK(refused["status"] == 422);
        CHECK(refused["errors"][0]["pointer"] == "/scenario/strip/reduction");
    }
    SUBCASE("an unknown or malformed base: 422 at /base") {
        for (const json& base : {json("stand-9"), json("default"), json("no/slash"), json(7),
                                 json{{"name", "stand-3"}, {"version", 2}}}) {
            CAPTURE(base.dump());
            const auto answer = post_json(client, "/v1/stability", {{"base", base}});
            REQUIRE(answer);
            CHECK(answer->status == 422);
            CHECK(body_json(answer)["errors"][0]["pointer"] == "/base");
        }
    }
    SUBCASE("base: null is no base") {
        const json answer =
            body_json(post_json(client, "/v1/roll-gap", {{"base", nullptr}, {"options", options}}));
        CHECK(answer["analysis"] == "roll_gap");
        CHECK_FALSE(answer.contains("base"));
    }
}

TEST_CASE("scenarios over http: the store unavailable is 503 for scenarios and base only") {
    TempDir dir;
    // A directory where the database file should be: SQLite cannot open it.
    const std::filesystem::path database = dir.path / "jobs.db";
    std::filesystem::create_directory(database);
    TestServer server(config_with_store("sqlite:" + database.string()));
    auto client = server.client();

    const auto unavailable = [](const httplib::Result& answer) {
        REQUIRE(answer);
        CHECK(answer->status == 503);
        CHECK(answer->get_header_value("Retry-After") == "1");
        CHECK(body_json(answer)["code"] == "store_unavailable");
    };
    unavailable(client.Get("/v1/scenarios"));
    unavailable(client.Get("/v1/scenarios/stand-3"));
    unavailable(put_scenario(client, "stand-3", json::object()));
    unavailable(client.Delete("/v1/scenarios/stand-3"));
    unavailable(post_json(client, "/v1/roll-gap", {{"base", "stand-3"}}));
    // Without base the store is never asked: analyses and the default scenario answer.
    CHECK(post_json(client, "/v1/roll-gap", {{"options", {{"distributions", false}}}})->status ==
          200);
    CHECK(post_json(client, "/v1/stability", {{"options", {{"critical_speed", false}}}})->status ==
          200);
    CHECK(client.Get("/v1/scenarios/default")->status == 200);
    // Validation before the store: a bad name or an invalid scenario is still a 422.
    CHECK(put_scenario(client, "default", json::object())->status == 422);
    CHECK(put_scenario(client, "stand-3", {{"strip", {{"reduction", 9}}}})->status == 422);

    // The database comes back: the service resumes without a restart.
    std::filesystem::remove(database);
    CHECK(eventually([&] { return put_scenario(client, "stand-3", json::object())->status == 201; },
                     std::chrono::milliseconds(5000)));
    CHECK(body_json(post_json(client, "/v1/roll-gap",
                              {{"base", "stand-3"},
                               {"options", {{"distributions", false}}}}))["base"]["version"] == 1);
}

TEST_CASE("scenarios: the command line has no store and answers base with 422 at /base") {
    std::istringstream in(R"({"analysis": "roll_gap", "base": "stand-3"})");
    std::ostringstream out, err;
    const std::vector<std::string_view> arguments{"run", "-"};
    const int status =
        service::run_cli(arguments, in, out, err, {service::serve, service::healthcheck});
    CHECK(status == service::exit_bad_input);
    const json problem = json::parse(out.str());
    CHECK(problem["status"] == 422);
    CHECK(problem["errors"][0]["pointer"] == "/base");
    CHECK(problem["detail"].get<std::string>().find("stored scenarios need the service") !=
          std::string::npos);

    // The resolved form (a job's stored request) is self-contained: it runs anywhere, echoing
    // the base it was resolved against.
    const service::Outcome resolved =
        service::evaluate({{"analysis", "roll_gap"},
                           {"base", {{"name", "stand-3"}, {"version", 4}}},
                           {"scenario", stand_patch},
                           {"options", {{"distributions", false}}}});
    REQUIRE(resolved.ok());
    CHECK(resolved.body["base"] == json{{"name", "stand-3"}, {"version", 4}});
}

TEST_CASE("scenarios: the OpenAPI document types the routes, the headers and base") {
    const json document = service::openapi_document();
    const json& paths = document["paths"];
    REQUIRE(paths.contains("/v1/scenarios"));
    REQUIRE(paths.contains("/v1/scenarios/{name}"));
    const json& named = paths["/v1/scenarios/{name}"];
    for (const char* status :
         {"200", "201", "400", "401", "412", "413", "415", "422", "428", "503"}) {
        CAPTURE(status);
        CHECK(named["put"]["responses"].contains(status));
    }
    for (const char* status : {"204", "404", "412", "422", "503"}) {
        CAPTURE(status);
        CHECK(named["delete"]["responses"].contains(status));
    }
    CHECK(named["get"]["responses"]["200"]["headers"].contains("ETag"));
    // a request's patch has no defaults (a generated client would require them); the answers'
    // component keeps them
    CHECK(named["put"]["requestBody"]["content"]["application/json"]["schema"]["$ref"] ==
          "#/components/schemas/ScenarioPatchInput");
    CHECK(document["components"]["schemas"]["ScenarioPatchInput"].dump().find("\"default\"") ==
          std::string::npos);
    CHECK(document["components"]["schemas"]["ScenarioPatch"]["properties"]["rolls"]["properties"]
                  ["speed_m_per_s"]
                      .contains("default"));
    const json& schemas = document["components"]["schemas"];
    CHECK(schemas["ScenarioName"]["pattern"] == std::string(api::stored_scenario_name_pattern));
    // Every request that carries a scenario patch may name a base; every answer may echo it.
    for (const char* request : {"AnalysisRequest", "RollGapRequest", "StabilityRequest",
                                "SweepRequest", "MapRequest", "CalibrateRequest"}) {
        CAPTURE(request);
        CHECK(schemas[request]["properties"].contains("base"));
    }
    CHECK(schemas["RollGapResponse"]["properties"]["base"]["$ref"] ==
          "#/components/schemas/ScenarioBase");
    CHECK_FALSE(json(schemas["RollGapResponse"]["required"]).dump().find("base") !=
                std::string::npos);
}

namespace {

httplib::Result put_mill(httplib::Client& client, const std::string& name, const json& body,
                         const httplib::Headers& headers = {}) {
    return client.Put(("/v1/mills/" + name).c_str(), headers, body.dump(), "application/json");
}

// A small mill (2 stands, docs/model.md §12.3) that differs from the default mill everywhere
// the answer depends on: its stand count, schedule, span and set point.
const json two_stands = {{"entry_thickness_mm", 1.88},
                         {"exit_thickness_mm", {1.6, 1.36}},
                         {"spans", {{"length_m", {5}}, {"tension_MPa", {60}}}},
                         {"stands", json::array({json::object(), json::object()})}};

}  // namespace

TEST_CASE("stored mills over http: create, read, list, base in a tandem request and in a job") {
    TempDir dir;
    TestServer server(config_with_store("sqlite:" + (dir.path / "jobs.db").string()));
    auto client = server.client();

    CHECK(body_json(client.Get("/v1/mills")) == json{{"mills", json::array()}});
    // The default mill is served from code, the document a tandem patch is merged onto.
    const json default_mill = body_json(client.Get("/v1/mills/default"));
    CHECK(default_mill["stands"].size() == 5);
    CHECK(put_mill(client, "default", json::object())->status == 422);

    auto created = put_mill(client, "line-2", two_stands);
    REQUIRE(created);
    CHECK(created->status == 201);
    CHECK(created->get_header_value("ETag") == "\"1\"");
    CHECK(created->get_header_value("Location") == "/v1/mills/line-2");
    const json stored = body_json(created);
    CHECK(stored["stands"].size() == 2);
    CHECK(stored["spans"]["tension_MPa"] == json::array({60.0}));
    CHECK(body_json(client.Get("/v1/mills/line-2")) == stored);
    const json listed = body_json(client.Get("/v1/mills"));
    REQUIRE(listed["mills"].size() == 1);
    CHECK(listed["mills"][0]["name"] == "line-2");
    // A mill is not a stand scenario: the stand collection does not list or serve it.
    CHECK(body_json(client.Get("/v1/scenarios"))["scenarios"].empty());
    CHECK(client.Get("/v1/scenarios/line-2")->status == 404);

    // Validation points into the body, per stand.
    json invalid = two_stands;
    invalid["stands"][1] = {{"rolls", {{"radius_mm", -5}}}};
    const json refused = body_json(put_mill(client, "line-3", invalid));
    CHECK(refused["status"] == 422);
    CHECK(refused["errors"][0]["pointer"] == "/stands/1/rolls/radius_mm");
    CHECK(client.Get("/v1/mills/line-3")->status == 404);  // nothing stored

    // A request with base: the stored mill with the request's patch on top, the same answer as
    // the whole mill sent by hand.
    const json options = {{"critical_speed", false}};
    const json patch = {{"speed_m_per_s", 12.0}};
    const json with_base = body_json(post_json(
        client, "/v1/tandem", {{"base", "line-2"}, {"tandem", patch}, {"options", options}}));
    json by_hand = two_stands;
    by_hand["speed_m_per_s"] = 12.0;
    const json without_base =
        body_json(post_json(client, "/v1/tandem", {{"tandem", by_hand}, {"options", options}}));
    REQUIRE(with_base.contains("result"));
    CHECK(with_base["base"] == json{{"name", "line-2"}, {"version", 1}});
    CHECK(with_base["tandem"] == without_base["tandem"]);
    CHECK(with_base["result"] == without_base["result"]);

    // A job stores the resolved request: it runs on the version it was answered with, even
    // after the mill is replaced.
    const std::string location = submit_job(
        client,
        {{"analysis", "tandem"}, {"base", "line-2"}, {"tandem", patch}, {"options", options}});
    json three = two_stands;
    three["exit_thickness_mm"] = {1.6, 1.36, 1.2};
    three["spans"] = {{"length_m", {5, 5}}, {"tension_MPa", {60, 60}}};
    three["stands"] = json::array({json::object(), json::object(), json::object()});
    REQUIRE(put_mill(client, "line-2", three, {{"If-Match", "\"1\""}})->status == 200);
    const json job = poll_until_finished(client, location);
    REQUIRE(job["state"] == "succeeded");
    CHECK(job["result"]["base"] == json{{"name", "line-2"}, {"version", 1}});
    CHECK(job["result"]["result"] == with_base["result"]);

    SUBCASE("a name holds one kind: a stand analysis cannot take a mill, nor a mill a stand") {
        const json stand_on_mill =
            body_json(post_json(client, "/v1/roll-gap", {{"base", "line-2"}}));
        CHECK(stand_on_mill["status"] == 422);
        CHECK(stand_on_mill["errors"][0]["pointer"] == "/base");
        REQUIRE(put_scenario(client, "stand-3", stand_patch)->status == 201);
        const json mill_on_stand =
            body_json(post_json(client, "/v1/tandem", {{"base", "stand-3"}, {"options", options}}));
        CHECK(mill_on_stand["status"] == 422);
        CHECK(mill_on_stand["errors"][0]["pointer"] == "/base");
        // Storing the other kind under a live name is a conflict, in either collection, whatever
        // the precondition.
        CHECK(put_mill(client, "stand-3", two_stands)->status == 409);
        CHECK(put_scenario(client, "line-2", json::object(), {{"If-Match", "\"2\""}})->status ==
              409);
        CHECK(put_scenario(client, "line-2", json::object())->status == 409);
        CHECK(client.Delete("/v1/scenarios/line-2")->status == 404);
        CHECK(client.Get("/v1/mills/line-2")->status == 200);
    }
    SUBCASE("delete, then the name is free for a stand; versions count on") {
        CHECK(client.Delete("/v1/mills/line-2", {{"If-Match", "\"2\""}})->status == 204);
        CHECK(client.Get("/v1/mills/line-2")->status == 404);
        const json refused_base = body_json(post_json(client, "/v1/tandem", {{"base", "line-2"}}));
        CHECK(refused_base["errors"][0]["pointer"] == "/base");
        auto stand = put_scenario(client, "line-2", json::object());
        REQUIRE(stand);
        CHECK(stand->status == 201);
        CHECK(stand->get_header_value("ETag") == "\"4\"");  // 1, 2 mill; 3 its delete
    }
}

TEST_CASE(
    "scenarios over http: PATCH merges onto the stored version, PUT replaces, ?version reads") {
    TempDir dir;
    TestServer server(config_with_store("sqlite:" + (dir.path / "jobs.db").string()));
    auto client = server.client();
    const json defaults = body_json(client.Get("/v1/scenarios/default"));
    REQUIRE(put_scenario(client, "stand-3", stand_patch)->status == 201);
    const auto patch = [&](const std::string& name, const json& body,
                           const httplib::Headers& headers = {},
                           const char* type = "application/merge-patch+json") {
        return client.Patch(("/v1/scenarios/" + name).c_str(), headers, body.dump(), type);
    };

    // One field edited; every other field keeps its stored value (not the default's).
    auto edited = patch("stand-3", {{"strip", {{"reduction", 0.3}}}}, {{"If-Match", "\"1\""}});
    REQUIRE(edited);
    CHECK(edited->status == 200);
    CHECK(edited->get_header_value("ETag") == "\"2\"");
    const json two = body_json(edited);
    CHECK(two["strip"]["reduction"] == 0.3);
    CHECK(two["strip"]["entry_thickness_mm"] == 2.0);
    CHECK(two["rolls"]["speed_m_per_s"] == 12.0);
    CHECK(body_json(client.Get("/v1/scenarios/stand-3")) == two);

    // PUT stays a full replacement: its body is a patch onto the default, so the fields it does
    // not name return to the default's.
    auto replaced =
        put_scenario(client, "stand-3", {{"strip", {{"reduction", 0.2}}}}, {{"If-Match", "\"2\""}});
    REQUIRE(replaced->status == 200);
    CHECK(body_json(replaced)["strip"]["entry_thickness_mm"] ==
          defaults["strip"]["entry_thickness_mm"]);
    CHECK(body_json(replaced)["rolls"]["speed_m_per_s"] == defaults["rolls"]["speed_m_per_s"]);

    // Every kept version reads back as it was, with who and when.
    auto first = client.Get("/v1/scenarios/stand-3?version=1");
    REQUIRE(first);
    CHECK(first->status == 200);
    CHECK(first->get_header_value("ETag") == "\"1\"");
    CHECK_FALSE(first->get_header_value("Last-Modified").empty());
    CHECK(first->get_header_value("Rollgap-Author") == "anonymous");
    CHECK(body_json(first)["strip"]["reduction"] == 0.25);
    CHECK(body_json(client.Get("/v1/scenarios/stand-3?version=2")) == two);
    CHECK(client.Get("/v1/scenarios/stand-3?version=0")->status == 422);
    CHECK(client.Get("/v1/scenarios/stand-3?version=x")->status == 422);
    CHECK(client.Get("/v1/scenarios/stand-3?version=99")->status == 404);

    // A stale version, an invalid value, a wrong media type, no such name, the default: refused,
    // and nothing stored.
    CHECK(patch("stand-3", {{"strip", {{"reduction", 0.1}}}}, {{"If-Match", "\"2\""}})->status ==
          412);
    auto invalid = patch("stand-3", {{"strip", {{"reduction", 2}}}});
    REQUIRE(invalid);
    CHECK(invalid->status == 422);
    CHECK(body_json(invalid)["errors"][0]["pointer"] == "/strip/reduction");
    CHECK(patch("stand-3", {{"strip", {{"reduction", 0.1}}}}, {}, "text/plain")->status == 415);
    CHECK(patch("stand-9", {{"strip", {{"reduction", 0.1}}}})->status == 404);
    auto on_default = patch("default", {{"strip", {{"reduction", 0.1}}}});
    CHECK(on_default->status == 405);
    CHECK(client.Get("/v1/scenarios/stand-3")->get_header_value("ETag") == "\"3\"");
    // application/json is taken as a merge patch too; without If-Match it merges onto the
    // version it read.
    auto plain = patch("stand-3", {{"rolls", {{"speed_m_per_s", 14}}}}, {}, "application/json");
    REQUIRE(plain->status == 200);
    CHECK(body_json(plain)["strip"]["reduction"] == 0.2);
    CHECK(body_json(plain)["rolls"]["speed_m_per_s"] == 14);
}

namespace {

// Force and slip observations of a coil (speeds low and high) of a stand whose viscosity is
// 6.0e-4 Pa s and asperity factor 0.8, each off by `error` of its uncertainty (force up, slip
// down): measurement errors, so that the coils disagree as real ones do.
json coil(double low, double high, double error) {
    json observations = json::array();
    for (const double v : {low, high}) {
        json stand = {{"lubricant", {{"viscosity_Pa_s", 6.0e-4}}},
                      {"friction", {{"asperity_factor", 0.8}}},
                      {"rolls", {{"speed_m_per_s", v}}}};
        const service::Outcome bite = service::evaluate({{"analysis", "roll_gap"},
                                                         {"scenario", stand},
                                                         {"options", {{"distributions", false}}}});
        REQUIRE(bite.ok());
        const double force = bite.body["result"]["force_kN"].get<double>();
        const double slip = bite.body["result"]["forward_slip"].get<double>();
        const json at = {{"rolls", {{"speed_m_per_s", v}}}};
        observations.push_back({{"scenario", at},
                                {"quantity", "roll_force_kN"},
                                {"value", force * (1.0 + 0.005 * error)},
                                {"standard_uncertainty", 0.005 * force}});
        observations.push_back({{"scenario", at},
                                {"quantity", "forward_slip"},
                                {"value", slip * (1.0 - 0.02 * error)},
                                {"standard_uncertainty", 0.02 * slip}});
    }
    return observations;
}

const json fitted_fields = {{{"field", "/lubricant/viscosity_Pa_s"}},
                            {{"field", "/friction/asperity_factor"}}};

}  // namespace

TEST_CASE("scenarios over http: a stored stand calibrated coil by coil keeps its posterior") {
    TempDir dir;
    TestServer server(config_with_store("sqlite:" + (dir.path / "jobs.db").string()));
    auto client = server.client();
    REQUIRE(put_scenario(client, "stand-2", json::object())->status == 201);
    const auto calibrate = [&](const json& body, const httplib::Headers& headers) {
        return client.Post("/v1/scenarios/stand-2/calibrate", headers, body.dump(),
                           "application/json");
    };
    // No posterior yet.
    CHECK(body_json(client.Get("/v1/scenarios/stand-2/calibrate"))["posterior"].is_null());

    const json first = {
        {"options", {{"parameters", fitted_fields}, {"observations", coil(6, 14, 1.0)}}}};
    // A calibration stores a new version: it needs If-Match.
    CHECK(calibrate(first, {})->status == 428);
    CHECK(calibrate(first, {{"If-Match", "\"7\""}})->status == 412);
    CHECK(client
              .Post("/v1/scenarios/stand-9/calibrate", {{"If-Match", "\"1\""}}, first.dump(),
                    "application/json")
              ->status == 404);
    CHECK(calibrate({{"scenario", json::object()}, {"options", first["options"]}},
                    {{"If-Match", "\"1\""}})
              ->status == 422);
    json invalid = first;
    invalid["options"]["parameters"][0]["field"] = "/lubricant/viscosity";
    CHECK(calibrate(invalid, {{"If-Match", "\"1\""}})->status == 422);

    auto one = calibrate(first, {{"If-Match", "\"1\""}});
    REQUIRE(one);
    REQUIRE_MESSAGE(one->status == 200, one->body);
    CHECK(one->get_header_value("ETag") == "\"2\"");
    const json answer = body_json(one);
    CHECK(answer["stored"] == json{{"name", "stand-2"}, {"version", 2}});
    CHECK(answer["options"]["joint_prior"].is_null());  // nothing stored to start from
    // The stored stand is the calibrated one, and keeps the posterior.
    const json stand = body_json(client.Get("/v1/scenarios/stand-2"));
    CHECK(stand["lubricant"]["viscosity_Pa_s"] == answer["result"]["parameters"][0]["value"]);
    const json kept = body_json(client.Get("/v1/scenarios/stand-2/calibrate"));
    CHECK(kept["version"] == 2);
    REQUIRE(kept["posterior"]["parameters"].size() == 2);
    CHECK(kept["posterior"]["correlation"] == answer["result"]["correlation"]);

    // The next coil: the stored posterior is the prior, and the stand ends where one fit of
    // both coils from the start ends (docs/model.md §11.6).
    const json second = {
        {"options", {{"parameters", fitted_fields}, {"observations", coil(10, 20, -0.7)}}}};
    auto two = calibrate(second, {{"If-Match", "\"2\""}});
    REQUIRE(two);
    REQUIRE_MESSAGE(two->status == 200, two->body);
    const json adapted = body_json(two);
    CHECK(adapted["options"]["joint_prior"]["parameters"].size() == 2);
    json both = coil(6, 14, 1.0);
    for (const json& o : coil(10, 20, -0.7)) both.push_back(o);
    const service::Outcome joint =
        service::evaluate({{"analysis", "calibrate"},
                           {"options", {{"parameters", fitted_fields}, {"observations", both}}}});
    REQUIRE(joint.ok());
    for (int k = 0; k < 2; ++k) {
        const json& s = adapted["result"]["parameters"][k];
        const json& j = joint.body["result"]["parameters"][k];
        CAPTURE(s.dump());
        CAPTURE(j.dump());
        CHECK(s["at_bound"].is_null());
        CHECK(std::abs(s["value"].get<double>() - j["value"].get<double>()) <
              0.02 * j["standard_error"].get<double>());
        // not the first coil's answer: the second coil moved it
        CHECK(std::abs(s["value"].get<double>() -
                       answer["result"]["parameters"][k]["value"].get<double>()) >
              0.1 * j["standard_error"].get<double>());
    }
    // A speed limit of the stored stand carries its uncertainty (docs/model.md §13.3), unless the
    // request moves a field the posterior describes.
    const auto speed_limit = [&](const json& body) {
        auto answered = client.Post("/v1/speed-limit", body.dump(), "application/json");
        REQUIRE(answered);
        REQUIRE_MESSAGE(answered->status == 200, answered->body);
        return body_json(answered);
    };
    const json limited =
        speed_limit({{"base", "stand-2"}, {"options", {{"what_to_change", false}}}});
    CHECK(limited["options"]["posterior"]["parameters"].size() == 2);
    CHECK(limited["result"]["uncertainty"]["propagated"] == true);
    CHECK(limited["result"]["uncertainty"]["standard_deviation_m_per_s"].get<double>() > 0.0);
    const json moved = speed_limit({{"base", "stand-2"},
                                    {"scenario", {{"lubricant", {{"viscosity_Pa_s", 7e-4}}}}},
                                    {"options", {{"what_to_change", false}}}});
    CHECK(moved["result"]["uncertainty"].is_null());
    const json without = speed_limit(
        {{"base", "stand-2"}, {"options", {{"what_to_change", false}, {"posterior", nullptr}}}});
    CHECK(without["result"]["uncertainty"].is_null());

    // Every version stays readable; a PUT replaces the stand and drops its posterior, a PATCH
    // of a field the posterior does not describe keeps it.
    CHECK(body_json(client.Get("/v1/scenarios/stand-2?version=2")) == stand);
    REQUIRE(client
                .Patch("/v1/scenarios/stand-2", {{"If-Match", "\"3\""}},
                       json{{"strip", {{"reduction", 0.2}}}}.dump(), "application/merge-patch+json")
                ->status == 200);
    CHECK(body_json(client.Get("/v1/scenarios/stand-2/calibrate"))["posterior"].is_object());
    REQUIRE(put_scenario(client, "stand-2", json::object(), {{"If-Match", "\"4\""}})->status ==
            200);
    CHECK(body_json(client.Get("/v1/scenarios/stand-2/calibrate"))["posterior"].is_null());
}
