// Stored scenarios as versions (issue 16, item 5; table scenario_versions, migration 2): a
// name's versions never repeat across delete and re-create, the count of stored scenarios is
// bounded, GET /v1/scenarios is paged, each version records its author, and a store made by
// the previous schema keeps its scenarios. The store on both backends (SQLite file, a
// PostgreSQL 15 started by the test), the endpoints against a real server in process.

#include <doctest/doctest.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <type_traits>

#include "service/store/job_store.h"
#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;
using namespace rollgap::service::store;

namespace {

struct SqliteDb {
    std::string dir = fresh_temp_dir();
    std::string setting() const { return "sqlite:" + dir + "/jobs.db"; }
};

PostgresServer& shared_postgres() {
    static PostgresServer server;
    return server;
}

struct PostgresDb {
    std::string dsn;
    PostgresDb() {
        static int databases = 0;
        auto& server = shared_postgres();
        if (!server.running()) server.start();
        REQUIRE_MESSAGE(server.running(), server.error());
        dsn = server.create_database("versions_test_" + std::to_string(++databases));
        REQUIRE(!dsn.empty());
    }
    std::string setting() const { return dsn; }
};

template <class Db>
std::shared_ptr<JobStore> open(const Db& db, StoreLimits limits = {}, Clock clock = system_millis) {
    auto store = open_store(db.setting(), limits, std::move(clock));
    REQUIRE_MESSAGE(store.ok(), status_name(store.status), ": ", store.detail);
    return *store.value;
}

service::ServerConfig config_with(std::size_t max_scenarios) {
    service::ServerConfig config = test_config();
    config.max_scenarios = max_scenarios;
    return config;
}

httplib::Result put(httplib::Client& client, const std::string& name,
                    const httplib::Headers& headers = {}) {
    return client.Put(("/v1/scenarios/" + name).c_str(), headers, "{}", "application/json");
}

}  // namespace

// Stored mills (kind `mill`, docs/http-api.md) share the table and a name's version counter
// with the stands: a name is one kind at a time, each collection lists its own kind, and a
// write or delete of the other kind never touches it.
TEST_CASE_TEMPLATE("scenario versions: a name holds a stand or a mill, never both", Db, SqliteDb,
                   PostgresDb) {
    Db db;
    auto store = open(db);
    const auto mill =
        store->put_scenario("line-2", "{\"m\":1}", std::nullopt, "alice", StoredKind::mill);
    REQUIRE(mill.ok());
    CHECK(mill.value->kind == StoredKind::mill);
    REQUIRE(store->put_scenario("stand-1", "{}", std::nullopt, "bob").ok());

    const auto read = store->get_scenario("line-2");
    REQUIRE(read.ok());
    CHECK(read.value->kind == StoredKind::mill);
    CHECK(store->get_scenario("stand-1").value->kind == StoredKind::stand);

    // Each kind's page lists only its own names; list_scenarios() is the stands'.
    const auto mills = store->list_scenario_page({10, std::nullopt, StoredKind::mill});
    REQUIRE(mills.ok());
    REQUIRE(mills.value->scenarios.size() == 1);
    CHECK(mills.value->scenarios[0].name == "line-2");
    CHECK(mills.value->scenarios[0].kind == StoredKind::mill);
    const auto stands = store->list_scenarios();
    REQUIRE(stands.ok());
    REQUIRE(stands.value->size() == 1);
    CHECK(stands.value->front().name == "stand-1");

    // The other kind over a live name: a conflict that says so, with or without the version.
    for (const std::optional<std::int64_t> version :
         {std::optional<std::int64_t>(), std::optional<std::int64_t>(1)}) {
        const auto over = store->put_scenario("line-2", "{}", version, "carol");
        CHECK(over.status == StoreStatus::conflict);
        CHECK(over.detail == kind_conflict_detail);
    }
    CHECK(store->delete_scenario("line-2", std::nullopt, "carol") == StoreStatus::not_found);
    CHECK(store->get_scenario("line-2").value->body == "{\"m\":1}");

    // Deleted as a mill, the name may become a stand; its versions count on.
    CHECK(store->delete_scenario("line-2", 1, "dave", StoredKind::mill) == StoreStatus::ok);
    const auto stand = store->put_scenario("line-2", "{}", std::nullopt, "erin");
    REQUIRE(stand.ok());
    CHECK(stand.value->version == 3);
    CHECK(stand.value->kind == StoredKind::stand);
}

TEST_CASE_TEMPLATE("scenario versions: never repeat for a name, authors, bounded history", Db,
                   SqliteDb, PostgresDb) {
    Db db;
    StoreLimits limits;
    limits.scenario_history = 3;
    auto store = open(db, limits);
    const auto first = store->put_scenario("mill-1", "{\"v\":1}", std::nullopt, "alice");
    REQUIRE(first.ok());
    CHECK(first.value->version == 1);
    CHECK(first.value->created);
    CHECK(store->delete_scenario("mill-1", 1, "bob") == StoreStatus::ok);
    CHECK(store->get_scenario("mill-1").status == StoreStatus::not_found);
    // The editor who read version 1 before the delete cannot write over the new scenario.
    CHECK(store->put_scenario("mill-1", "{}", 1, "carol").status == StoreStatus::conflict);
    const auto again = store->put_scenario("mill-1", "{\"v\":3}", std::nullopt, "carol");
    REQUIRE(again.ok());
    CHECK(again.value->version == 3);  // 2 was the delete
    CHECK(again.value->created);
    CHECK(store->put_scenario("mill-1", "{}", 1, "carol").status == StoreStatus::conflict);
    for (std::int64_t v = 3; v < 8; ++v)
        REQUIRE(
            store->put_scenario("mill-1", "{\"v\":" + std::to_string(v + 1) + "}", v, "dave").ok());
    const auto got = store->get_scenario("mill-1");
    REQUIRE(got.ok());
    CHECK(got.value->version == 8);
    CHECK(got.value->body == "{\"v\":8}");
    CHECK(got.value->author == "dave");
    const auto listed = store->list_scenario_page({});
    REQUIRE(listed.ok());
    REQUIRE(listed.value->scenarios.size() == 1);
    CHECK(listed.value->scenarios[0].author == "dave");
    CHECK(listed.value->scenarios[0].version == 8);
}

TEST_CASE_TEMPLATE("scenario versions: the count is bounded, pages by name", Db, SqliteDb,
                   PostgresDb) {
    Db db;
    StoreLimits limits;
    limits.max_scenarios = 3;
    auto store = open(db, limits);
    for (const char* name : {"c", "a", "b"})
        REQUIRE(store->put_scenario(name, "{}", std::nullopt).ok());
    CHECK(store->put_scenario("d", "{}", std::nullopt).status == StoreStatus::full);
    CHECK(store->put_scenario("a", "{}", 1).ok());  // replacing is not a new one
    REQUIRE(store->delete_scenario("b", std::nullopt) == StoreStatus::ok);
    CHECK(store->put_scenario("d", "{}", std::nullopt).ok());
    CHECK(store->put_scenario("b", "{}", std::nullopt).status == StoreStatus::full);

    const auto first = store->list_scenario_page({2, std::nullopt});
    REQUIRE(first.ok());
    REQUIRE(first.value->scenarios.size() == 2);
    CHECK(first.value->scenarios[0].name == "a");
    CHECK(first.value->scenarios[1].name == "c");
    REQUIRE(first.value->next_cursor);
    const auto second = store->list_scenario_page({2, first.value->next_cursor});
    REQUIRE(second.ok());
    REQUIRE(second.value->scenarios.size() == 1);
    CHECK(second.value->scenarios[0].name == "d");
    CHECK_FALSE(second.value->next_cursor);
    CHECK(store->list_scenario_page({2, std::string("../x")}).status == StoreStatus::invalid);
}

TEST_CASE_TEMPLATE(
    "scenario versions: deleted names are bounded, a name that lost its marker "
    "still never repeats a version",
    Db, SqliteDb, PostgresDb) {
    Db db;
    StoreLimits limits;
    limits.deleted_names = 2;
    // "Oldest" needs distinct times: the wall clock gives several writes one millisecond (and
    // the store then orders ties by name). A clock that ticks at every reading does not.
    auto ticks = std::make_shared<std::atomic<Millis>>(1'700'000'000'000);
    auto store = open(db, limits, [ticks] { return ticks->fetch_add(1); });
    // "old" reaches version 5, and its delete marker holds 6.
    REQUIRE(store->put_scenario("old", "{}", std::nullopt).ok());
    for (std::int64_t v = 1; v < 5; ++v) REQUIRE(store->put_scenario("old", "{}", v).ok());
    REQUIRE(store->delete_scenario("old", 5) == StoreStatus::ok);
    // Three more names created and deleted push "old"'s marker out of the two kept.
    std::int64_t n3_created = 0;
    for (const char* name : {"n1", "n2", "n3"}) {
        const auto created = store->put_scenario(name, "{}", std::nullopt);
        REQUIRE(created.ok());
        n3_created = created.value->version;
        REQUIRE(store->delete_scenario(name, std::nullopt) == StoreStatus::ok);
    }
    // A name never stored starts above the floor the dropped markers left (old's 6).
    CHECK(n3_created > 6);
    // An editor's stale If-Match from before the delete still cannot write, and the name starts
    // above every version it ever had.
    CHECK(store->put_scenario("old", "{}", 5).status == StoreStatus::conflict);
    const auto again = store->put_scenario("old", "{}", std::nullopt);
    REQUIRE(again.ok());
    CHECK(again.value->version > 6);
    CHECK(again.value->created);
    // A name whose marker is still kept counts on from it (the delete was n3_created + 1).
    const auto n3 = store->put_scenario("n3", "{}", std::nullopt);
    REQUIRE(n3.ok());
    CHECK(n3.value->version == n3_created + 2);
    if constexpr (std::is_same_v<Db, SqliteDb>) {
        // The rows themselves: at most two deleted names' markers (n2's; n3 lives again), plus
        // the floor's row.
        const std::string file = db.dir + "/jobs.db";
        const std::string out = db.dir + "/count.txt";
        REQUIRE(std::system(("sqlite3 '" + file +
                             "' \"SELECT COUNT(*) FROM scenario_versions WHERE deleted = 1 AND "
                             "name <> ''\" > '" +
                             out + "'")
                                .c_str()) == 0);
        std::ifstream counted(out);
        int markers = -1;
        counted >> markers;
        CHECK(markers >= 1);
        CHECK(markers <= 3);  // n2's marker, n3's (kept in its history), at most one more
    }
}

TEST_CASE("scenario versions: a store of the previous schema keeps its scenarios and versions") {
    // The version-1 schema as it was shipped (service/store/migrations.cpp before issue 16),
    // made with the sqlite3 program, then opened by this build.
    const std::string dir = fresh_temp_dir();
    const std::string file = dir + "/jobs.db";
    const std::string sql =
        "CREATE TABLE schema_migrations (version BIGINT PRIMARY KEY, applied_ms BIGINT NOT NULL);"
        "INSERT INTO schema_migrations VALUES (1, 0);"
        "CREATE TABLE jobs (seq INTEGER PRIMARY KEY AUTOINCREMENT, id TEXT NOT NULL UNIQUE,"
        " analysis TEXT NOT NULL, request TEXT NOT NULL, state TEXT NOT NULL,"
        " progress DOUBLE PRECISION NOT NULL DEFAULT 0, result TEXT, problem TEXT,"
        " instance TEXT NOT NULL, worker TEXT, created_ms BIGINT NOT NULL, started_ms BIGINT,"
        " finished_ms BIGINT, deadline_ms BIGINT NOT NULL,"
        " cancel_requested INTEGER NOT NULL DEFAULT 0, idempotency_key TEXT UNIQUE,"
        " body_hash TEXT NOT NULL, points BIGINT NOT NULL, chunk_size BIGINT NOT NULL,"
        " chunks BIGINT NOT NULL);"
        "CREATE INDEX jobs_state_seq ON jobs (state, seq);"
        "CREATE INDEX jobs_finished ON jobs (finished_ms);"
        "CREATE TABLE chunks (job_id TEXT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,"
        " idx BIGINT NOT NULL, job_seq BIGINT NOT NULL, begin_point BIGINT NOT NULL,"
        " end_point BIGINT NOT NULL, state TEXT NOT NULL, lease_token TEXT, lease_owner TEXT,"
        " lease_until_ms BIGINT, result TEXT, PRIMARY KEY (job_id, idx));"
        "CREATE INDEX chunks_claim ON chunks (state, job_seq, idx);"
        "CREATE TABLE scenarios (name TEXT PRIMARY KEY, body TEXT NOT NULL,"
        " version BIGINT NOT NULL, updated_ms BIGINT NOT NULL);"
        "INSERT INTO scenarios VALUES ('mill-7', '{\"old\":true}', 4, 1700000000000);";
    std::ofstream(dir + "/v1.sql") << sql;
    REQUIRE(std::system(("sqlite3 '" + file + "' < '" + dir + "/v1.sql'").c_str()) == 0);
    auto opened = open_store("sqlite:" + file);
    REQUIRE_MESSAGE(opened.ok(), opened.detail);
    auto store = *opened.value;
    const auto kept = store->get_scenario("mill-7");
    REQUIRE(kept.ok());
    CHECK(kept.value->version == 4);
    CHECK(kept.value->body == "{\"old\":true}");
    CHECK(kept.value->author == "unknown");
    CHECK(store->put_scenario("mill-7", "{}", 4, "alice").value->version == 5);
}

TEST_CASE("scenario versions over http: a stale If-Match after delete and re-create is 412") {
    TestServer server(config_with(1000));
    auto client = server.client();
    REQUIRE(put(client, "stand-9")->status == 201);
    CHECK(put(client, "stand-9")->status == 428);  // replacing needs If-Match
    REQUIRE(client.Delete("/v1/scenarios/stand-9")->status == 204);
    const auto recreated = put(client, "stand-9");
    REQUIRE(recreated);
    CHECK(recreated->status == 201);
    CHECK(recreated->get_header_value("ETag") == "\"3\"");
    CHECK(recreated->get_header_value("Location") == "/v1/scenarios/stand-9");
    // The editor who read the first stand-9 (ETag "1") does not overwrite the new one.
    CHECK(put(client, "stand-9", {{"If-Match", "\"1\""}})->status == 412);
    CHECK(put(client, "stand-9", {{"If-Match", "\"3\""}})->status == 200);
}

TEST_CASE("scenario versions over http: --max-scenarios is 507, GET /v1/scenarios pages") {
    TestServer server(config_with(3));
    auto client = server.client();
    for (const char* name : {"s-b", "s-a", "s-c"}) REQUIRE(put(client, name)->status == 201);
    const auto full = put(client, "s-d");
    REQUIRE(full);
    CHECK(full->status == 507);
    CHECK(full->get_header_value("Content-Type") == "application/problem+json");
    CHECK(json::parse(full->body)["code"] == "insufficient_storage");
    CHECK(put(client, "s-a", {{"If-Match", "\"1\""}})->status == 200);

    const json first = body_json(client.Get("/v1/scenarios?limit=2"));
    REQUIRE(first["scenarios"].size() == 2);
    CHECK(first["scenarios"][0]["name"] == "s-a");
    CHECK(first["scenarios"][0]["author"] == "anonymous");
    CHECK(first["scenarios"][1]["name"] == "s-b");
    REQUIRE(first.contains("next_cursor"));
    const json second = body_json(client.Get(
        ("/v1/scenarios?limit=2&cursor=" + first["next_cursor"].get<std::string>()).c_str()));
    REQUIRE(second["scenarios"].size() == 1);
    CHECK(second["scenarios"][0]["name"] == "s-c");
    CHECK_FALSE(second.contains("next_cursor"));
    CHECK(body_json(client.Get("/v1/scenarios"))["scenarios"].size() == 3);

    for (const std::string query : {"limit=0", "limit=201", "limit=x", "cursor=..%2Fx"}) {
        CAPTURE(query);
        const auto refused = client.Get(("/v1/scenarios?" + query).c_str());
        REQUIRE(refused);
        CHECK(refused->status == 422);
        const json problem = json::parse(refused->body);
        CHECK(problem["errors"][0]["pointer"] ==
              (query.starts_with("limit") ? "/query/limit" : "/query/cursor"));
    }
}
