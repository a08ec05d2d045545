// Batches (service/analyses/batch.h) through the one facade: every row is its item's own answer
// (its headline read from the answer the item gives as a request of its own, written out here
// by hand, not by the code under test), an item that fails carries its own problem with
// pointers into the batch and the batch still succeeds, the shared parts and the item's merge
// as RFC 7396 says (null restores the default, not the batch's value), speed limits skip their
// sensitivities unless asked, rows assembled from chunks are the whole batch's byte for byte,
// and a malformed batch is one 422 listing every violation.

#include <doctest/doctest.h>

#include <atomic>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/batch_json.h"
#include "service/chunked.h"
#include "service/csv_answer.h"
#include "service/evaluate.h"
#include "support/mill_requests.h"
#include "support/approx.h"

using nlohmann::json;
using namespace rollgap;

namespace batch_test {

// A narrow, coarse critical-speed search: each speed limit takes a few milliseconds.
const json cheap_search = {{"speed_min_m_per_s", 10},
                           {"speed_max_m_per_s", 30},
                           {"speed_step_m_per_s", 0.5},
                           {"relative_tolerance", 1e-4}};

json speed_limit_options() {
    json options = cheap_search;
    options["max_roll_force_kN"] = 7000;
    options["max_power_kW"] = 6000;
    return options;
}

// Four coils of one stand: two speeds, a thinner emulsion, and one with a reduction of 300 %.
json four_coils() {
    return {{"analysis", "batch"},
            {"options",
             {{"analysis", "speed_limit"},
              {"scenario", {{"tension", {{"back", {{"stress_MPa", 20}}}}}}},
              {"options", speed_limit_options()},
              {"items",
               {{{"label", "C-101"}},
                {{"label", "C-102"}, {"scenario", {{"rolls", {{"speed_m_per_s", 15}}}}}},
                {{"label", "C-103"}, {"scenario", {{"strip", {{"reduction", 3}}}}}},
                {{"label", "C-104"},
                 {"scenario", {{"lubricant", {{"viscosity_Pa_s", 4e-4}}}}},
                 {"options", {{"max_power_kW", nullptr}}}}}}}}};
}

json answer(const json& request) {
    const service::Outcome outcome = service::evaluate(request);
    CAPTURE(outcome.body.dump().substr(0, 800));
    REQUIRE(outcome.ok());
    return outcome.body;
}

}  // namespace batch_test

using namespace batch_test;

TEST_CASE("batch: each row is its item's own answer, and a failing item carries its own problem") {
    const json batch = answer(four_coils());
    const json& result = batch["result"];
    CHECK(result["analysis"] == "speed_limit");
    CHECK(result["items_total"] == 4);
    CHECK(result["succeeded"] == 3);
    CHECK(result["failed"] == 1);
    REQUIRE(result["items"].size() == 4);
    // The echo leaves the items out (the rows name them) and counts them.
    CHECK_FALSE(batch["options"].contains("items"));
    CHECK(batch["options"]["items_total"] == 4);
    CHECK_FALSE(batch.contains("scenario"));

    // The same coils as requests of their own, written out by hand: the batch's patch, then the
    // item's; its options, then the item's; sensitivities off, as a batch runs them.
    json plain = speed_limit_options();
    plain["what_to_change"] = false;
    json without_power = plain;
    without_power.erase("max_power_kW");
    const std::vector<json> own{
        {{"analysis", "speed_limit"},
         {"scenario", {{"tension", {{"back", {{"stress_MPa", 20}}}}}}},
         {"options", plain}},
        {{"analysis", "speed_limit"},
         {"scenario",
          {{"tension", {{"back", {{"stress_MPa", 20}}}}}, {"rolls", {{"speed_m_per_s", 15}}}}},
         {"options", plain}},
        {},
        {{"analysis", "speed_limit"},
         {"scenario",
          {{"tension", {{"back", {{"stress_MPa", 20}}}}},
           {"lubricant", {{"viscosity_Pa_s", 4e-4}}}}},
         {"options", without_power}},
    };
    for (const std::size_t i : {0U, 1U, 3U}) {
        CAPTURE(i);
        const json& row = result["items"][i];
        CHECK(row["index"] == i);
        CHECK(row["status"] == "ok");
        CHECK(row["problem"].is_null());
        const json alone = answer(own[i]);
        CHECK(row["headline"] == api::batch_headline("speed_limit", alone["result"]));
        // The figures a plant reads, straight from the answer.
        CHECK(row["headline"]["advised_speed_m_per_s"] == alone["result"]["advised_speed_m_per_s"]);
        CHECK(row["headline"]["binding_limit"] == alone["result"]["binding_limit"]);
        const double operating = alone["result"]["operating_speed_m_per_s"];
        const double advised = alone["result"]["advised_speed_m_per_s"];
        CHECK(row["headline"]["speed_margin_m_per_s"].get<double>() ==
              rollgap::test::approx(advised - operating).epsilon(1e-12));
        CHECK(row["headline"]["utilisation"].get<double>() ==
              rollgap::test::approx(operating / advised).epsilon(1e-12));
        CHECK(row["headline"]["best_change_field"].is_null());  // not asked
    }
    CHECK(result["items"][0]["label"] == "C-101");
    // The thinner emulsion's coil has no power limit: the item's null removed the batch's.
    CHECK(result["items"][3]["headline"]["binding_limit"] != "power");

    // The coil with a 300 % reduction: its own 422, pointing into the batch.
    const json& failed = result["items"][2];
    CHECK(failed["label"] == "C-103");
    CHECK(failed["status"] == "failed");
    CHECK(failed["headline"].is_null());
    CHECK(failed["problem"]["status"] == 422);
    CHECK(failed["problem"]["errors"][0]["pointer"] == "/options/items/2/scenario/strip/reduction");
    CHECK(failed["problem"]["errors"][0]["bound"] == "(0, 0.7]");
}

TEST_CASE("batch: null in an item's patch restores the default, not the batch's value") {
    json request = four_coils();
    request["options"]["scenario"] = {{"strip", {{"reduction", 0.25}}}};
    request["options"]["items"] = {
        {{"label", "shared"}},
        {{"label", "default"}, {"scenario", {{"strip", {{"reduction", nullptr}}}}}}};
    request["options"]["analysis"] = "roll_gap";
    request["options"].erase("options");
    const json rows = answer(request)["result"]["items"];
    const json shared = answer(
        {{"analysis", "roll_gap"}, {"scenario", {{"strip", {{"reduction", 0.25}}}}}})["result"];
    const json plain = answer({{"analysis", "roll_gap"}})["result"];
    CHECK(rows[0]["headline"] == api::batch_headline("roll_gap", shared));
    CHECK(rows[1]["headline"] == api::batch_headline("roll_gap", plain));
    CHECK(rows[0]["headline"] != rows[1]["headline"]);
    // Any other analysis' headline: its result's top-level scalars, as they are.
    for (const auto& entry : rows[1]["headline"].items()) {
        const std::string name = entry.key();
        CAPTURE(name);
        CHECK_FALSE(entry.value().is_structured());
        CHECK(plain.at(json::json_pointer("/" + name)) == entry.value());
    }
}

TEST_CASE("batch: an item's atypical value is a warning in its row, pointing into the batch") {
    // 0.5 Pa.s is above any emulsion's viscosity (typical up to 0.2 Pa.s): likely 0.5 mPa.s
    json request = {
        {"analysis", "batch"},
        {"options",
         {{"analysis", "roll_gap"},
          {"options", {{"distributions", false}}},
          {"items",
           {{{"label", "typical"}},
            {{"label", "slip"}, {"scenario", {{"lubricant", {{"viscosity_Pa_s", 0.5}}}}}}}}}}};
    const json batch = answer(request);
    const json rows = batch["result"]["items"];
    REQUIRE(rows.size() == 2);
    CHECK_FALSE(rows[0].contains("warnings"));
    REQUIRE(rows[1].contains("warnings"));
    REQUIRE(rows[1]["warnings"].size() == 1);
    const json& warning = rows[1]["warnings"][0];
    CHECK(warning["pointer"] == "/options/items/1/scenario/lubricant/viscosity_Pa_s");
    CHECK(warning["likely"]["key"] == "viscosity_mPa_s");
    // the same warning as the item's own request gets
    const json alone = answer({{"analysis", "roll_gap"},
                               {"scenario", {{"lubricant", {{"viscosity_Pa_s", 0.5}}}}},
                               {"options", {{"distributions", false}}}});
    CHECK(alone["warnings"][0]["likely"] == warning["likely"]);
    CHECK(alone["warnings"][0]["detail"] == warning["detail"]);
    // and in the sheet, the pointer with its likely unit
    const service::CsvAnswer csv = service::csv_answer(batch, "");
    REQUIRE(csv.status == 200);
    CHECK(csv.body.find(",/options/items/1/scenario/lubricant/viscosity_Pa_s likely "
                        "viscosity_mPa_s\r\n") != std::string::npos);
}

TEST_CASE("batch: a speed limit's sensitivities are computed when the batch asks for them") {
    json request = four_coils();
    request["options"]["items"] = {{{"label", "asked"}, {"options", {{"what_to_change", true}}}},
                                   {{"label", "not asked"}}};
    const json rows = answer(request)["result"]["items"];
    CHECK(rows[0]["headline"]["best_change_field"].is_string());
    CHECK(rows[0]["headline"]["best_change_gain_m_per_s"].get<double>() > 0.0);
    CHECK(rows[1]["headline"]["best_change_field"].is_null());
}

TEST_CASE("batch: rows assembled from chunks are the whole batch's, byte for byte") {
    const json request = four_coils();
    const service::Outcome whole = service::evaluate(request);
    REQUIRE(whole.ok());
    REQUIRE(service::chunkable_points(request) == 4);
    json documents = json::array();
    for (const auto& [begin, end] : {std::pair{0, 1}, std::pair{1, 3}, std::pair{3, 4}}) {
        const service::Outcome chunk = service::evaluate_points(request, begin, end);
        REQUIRE(chunk.ok());
        // Through text, as the store keeps them.
        for (const json& row : json::parse(chunk.body.dump())) documents.push_back(row);
    }
    const service::Outcome assembled = service::assemble_points(request, documents);
    REQUIRE(assembled.ok());
    CHECK(assembled.body.dump() == whole.body.dump());
}

TEST_CASE("batch: a stopped batch is cancelled, not a batch of failed rows") {
    std::atomic<int> polls{0};
    core::Control control;
    control.cancelled = [&polls] { return ++polls > 3; };
    const service::Outcome outcome = service::evaluate(four_coils(), control);
    CHECK(outcome.problem == api::ProblemCode::cancelled);
}

TEST_CASE("batch: a mill's analysis runs per item with the mill's patches") {
    json options = {{"critical_speed", false}};
    const json request = {{"analysis", "batch"},
                          {"options",
                           {{"analysis", "tandem"},
                            {"tandem", test::two_stands},
                            {"options", options},
                            {"items",
                             {{{"label", "m1"}},
                              {{"label", "m2"}, {"tandem", {{"speed_m_per_s", 12}}}},
                              {{"label", "wrong subject"}, {"scenario", json::object()}}}}}}};
    // An item with a stand's patch in a mill's batch is the batch's violation (its shape).
    const json refused = test::refusal_of(request);
    CHECK(refused["errors"][0]["pointer"] == "/options/items/2/scenario");
    json fine = request;
    fine["options"]["items"].erase(2);
    const json rows = answer(fine)["result"]["items"];
    REQUIRE(rows.size() == 2);
    json second = {{"analysis", "tandem"}, {"tandem", test::two_stands}, {"options", options}};
    second["tandem"]["speed_m_per_s"] = 12;
    CHECK(rows[1]["status"] == "ok");
    CHECK(rows[1]["headline"] == api::batch_headline("tandem", answer(second)["result"]));
    CHECK(rows[0]["headline"] != rows[1]["headline"]);
}

TEST_CASE("batch: a malformed batch is one 422 listing every violation") {
    json request = four_coils();
    request["options"]["items"][1].erase("label");
    request["options"]["items"][2]["label"] = std::string(129, 'x');
    request["options"]["items"][3]["colour"] = "red";
    request["options"]["extra"] = 1;
    const json problem = test::refusal_of(request);
    std::vector<std::string> pointers;
    for (const json& error : problem["errors"]) pointers.push_back(error["pointer"]);
    CAPTURE(problem.dump());
    for (const char* pointer : {"/options/items/1/label", "/options/items/2/label",
                                "/options/items/3/colour", "/options/extra"}) {
        CHECK(std::find(pointers.begin(), pointers.end(), pointer) != pointers.end());
    }

    // 10,001 items: the bound, before any item is looked at.
    json many = four_coils();
    many["options"]["items"] = json::array();
    for (std::size_t i = 0; i <= api::max_batch_items; ++i)
        many["options"]["items"].push_back({{"label", "c"}});
    const json too_many = test::refusal_of(many);
    CHECK(too_many["errors"][0]["pointer"] == "/options/items");
    CHECK(too_many["errors"][0]["bound"] == "[1, 10000] items");

    // Items are analyses that run whole; a sweep splits into points of its own.
    json sweep = four_coils();
    sweep["options"]["analysis"] = "sweep";
    CHECK(test::refusal_of(sweep)["errors"][0]["pointer"] == "/options/analysis");
    json nested = four_coils();
    nested["options"]["analysis"] = "batch";
    CHECK(test::refusal_of(nested)["errors"][0]["pointer"] == "/options/analysis");

    // The batch's subject is in its options.
    json top = four_coils();
    top["scenario"] = json::object();
    CHECK(test::refusal_of(top)["errors"][0]["pointer"] == "/scenario");
}

TEST_CASE("batch: without the service a stored base is the item's problem, not the batch's") {
    json request = four_coils();
    request["options"]["items"][0]["base"] = "stand-3";
    const json rows = answer(request)["result"]["items"];
    CHECK(rows[0]["status"] == "failed");
    CHECK(rows[0]["problem"]["errors"][0]["pointer"] == "/options/items/0/base");
    CHECK(rows[1]["status"] == "ok");
}

TEST_CASE("batch: the CSV sheet has one row per item, the headline's figures and the problem") {
    const json batch = answer(four_coils());
    const service::CsvAnswer csv = service::csv_answer(batch, "");
    REQUIRE(csv.status == 200);
    std::vector<std::string> lines;
    for (std::size_t at = 0; at < csv.body.size();) {
        const std::size_t end = csv.body.find("\r\n", at);
        lines.push_back(csv.body.substr(at, end - at));
        at = end + 2;
    }
    REQUIRE(lines.size() == 5);  // the header and four items
    const std::string& header = lines[0];
    CHECK(header.starts_with("index,label,status,base_name,base_version,"));
    CHECK(header.ends_with(",problem_type,problem_title,problem_detail,warnings"));
    // speed_limit's own status beside the item's, renamed.
    CHECK(header.find(",result_status,") != std::string::npos);
    CHECK(header.find(",advised_speed_m_per_s,") != std::string::npos);
    CHECK(lines[1].starts_with("0,C-101,ok,,,"));
    CHECK(lines[3].starts_with("2,C-103,failed,,,"));
    CHECK(lines[3].find("Scenario is invalid") != std::string::npos);
}

TEST_CASE(
    "batch: a label a spreadsheet would take for a formula is text in the CSV, as given in JSON") {
    json request = four_coils();
    request["options"]["items"] = {{{"label", "=HYPERLINK(\"http://x\",\"C-1\")"}},
                                   {{"label", "-7"}}};
    const json batch = answer(request);
    CHECK(batch["result"]["items"][0]["label"] == "=HYPERLINK(\"http://x\",\"C-1\")");
    const service::CsvAnswer csv = service::csv_answer(batch, "");
    REQUIRE(csv.status == 200);
    CHECK(csv.body.find("\r\n0,\"'=HYPERLINK(\"\"http://x\"\",\"\"C-1\"\")\",ok,") !=
          std::string::npos);
    CHECK(csv.body.find("\r\n1,\"'-7\",ok,") != std::string::npos);
}
