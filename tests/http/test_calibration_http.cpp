// The analysis "calibrate" over HTTP: the synchronous route and a job give the same fit; a
// running calibration job reports progress and stops when it is deleted.

#include <doctest/doctest.h>

#include <string>

#include "service/evaluate.h"
#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;

namespace {

// Flow stress from two roll forces: a fit of a few bite solves.
const json small_fit = {
    {"parameters", {{{"field", "/strip/flow_stress_MPa"}}}},
    {"observations",
     {{{"scenario", {{"rolls", {{"speed_m_per_s", 5}}}}},
       {"quantity", "roll_force_kN"},
       {"value", 9500},
       {"standard_uncertainty", 50}},
      {{"quantity", "roll_force_kN"}, {"value", 7000}, {"standard_uncertainty", 50}}}}};

json poll(httplib::Client& client, const std::string& location,
          const std::function<bool(const json&)>& until) {
    json document;
    REQUIRE(eventually(
        [&] {
            const auto result = client.Get(location.c_str());
            if (!result || result->status != 200) return false;
            document = json::parse(result->body);
            return until(document);
        },
        std::chrono::milliseconds(60000)));
    return document;
}

}  // namespace

TEST_CASE("calibrate over http: POST /v1/calibrate and a job give the facade's fit") {
    TestServer server;
    auto client = server.client();
    const json expected =
        service::evaluate({{"analysis", "calibrate"}, {"options", small_fit}}).body;
    REQUIRE(expected["result"]["status"] == "converged");

    const auto sync = post_json(client, "/v1/calibrate", {{"options", small_fit}});
    REQUIRE(sync);
    CHECK(sync->status == 200);
    CHECK(json::parse(sync->body) == expected);

    const auto created =
        post_json(client, "/v1/jobs", {{"analysis", "calibrate"}, {"options", small_fit}});
    REQUIRE(created);
    REQUIRE(created->status == 202);
    const std::string location = created->get_header_value("Location");
    const json done = poll(client, location, [](const json& d) {
        return d["state"] != "queued" && d["state"] != "running";
    });
    CHECK(done["state"] == "succeeded");
    CHECK(done["progress"] == 1.0);
    CHECK(done["result"] == expected);

    // Invalid options are refused at creation, with the pointer.
    const auto refused = post_json(client, "/v1/calibrate",
                                   {{"options",
                                     {{"parameters", {{{"field", "/strip/nope"}}}},
                                      {"observations", small_fit["observations"]}}}});
    REQUIRE(refused);
    CHECK(refused->status == 422);
    CHECK(refused->body.find("/options/parameters/0/field") != std::string::npos);
}

TEST_CASE("calibrate over http: a running job reports progress and stops when deleted") {
    TestServer server;
    auto client = server.client();
    // Critical speeds over the full default range: seconds of work.
    const json slow = {
        {"analysis", "calibrate"},
        {"options",
         {{"parameters",
           {{{"field", "/mill/rayleigh/damping_ratio"}},
            {{"field", "/tension/back/span_length_m"}}}},
          {"observations",
           {{{"quantity", "critical_speed_m_per_s"}, {"value", 30}, {"standard_uncertainty", 0.2}},
            {{"scenario", {{"strip", {{"reduction", 0.25}}}}},
             {"quantity", "critical_speed_m_per_s"},
             {"value", 25},
             {"standard_uncertainty", 0.2}}}}}}};
    const auto created = post_json(client, "/v1/jobs", slow);
    REQUIRE(created);
    REQUIRE(created->status == 202);
    const std::string location = created->get_header_value("Location");
    const json running = poll(client, location, [](const json& d) {
        return d["state"] != "queued" &&
               (d["state"] != "running" || d["progress"].get<double>() > 0.0);
    });
    REQUIRE(running["state"] == "running");
    CHECK(running["progress"].get<double>() > 0.0);
    CHECK(running["progress"].get<double>() < 1.0);
    const auto deleted = client.Delete(location.c_str());
    REQUIRE(deleted);
    const json stopped =
        poll(client, location, [](const json& d) { return d["state"] != "running"; });
    CHECK(stopped["state"] == "cancelled");
}
