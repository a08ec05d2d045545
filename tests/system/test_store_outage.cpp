// The job store when the database misbehaves, with real `rollgap serve` processes (the built
// program): PostgreSQL at its connection bound under rounds of concurrent job polls, a
// PostgreSQL restart, a partition through a TCP relay started here (support/tcp_relay.h), a
// SQLite file the service cannot write (run as `nobody`) and one deleted under it. The store
// executor (service/store/store_executor.h) bounds the connections and gives every store call a
// deadline; health and metrics read the background probe's last answer (docs/job-store.md).
//
// Settings the replicas get by environment (ROLLGAP_STORE_*), not flags, so that the same test
// can run a program built before them (the "before" figures of the change).
// Cost: each case a few seconds (PostgreSQL start-up dominates), also under ASan.

#include <doctest/doctest.h>

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/replicas.h"
#include "support/tcp_relay.h"

using namespace rollgap::test;
using nlohmann::json;
using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

namespace {

// One server for every case (a cluster's initdb costs seconds): each case has a database of
// its own; its bound is small so that the first case runs at it.
PostgresServer& shared_postgres() {
    static PostgresServer server(16);
    if (!server.running()) server.start();
    REQUIRE_MESSAGE(server.running(), server.error());
    return server;
}

const json quick_job = {{"analysis", "roll_gap"}, {"options", {{"distributions", false}}}};

double ms_since(Clock::time_point since) {
    return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
}

std::optional<double> store_up(const Replica& replica);

// Submits `request` (202) and waits for its end; the job's id. First waits (bounded) until the
// replica has opened its store in the background: a request during that waits only the store
// deadline.
std::string finished_job(const Replica& replica, const json& request = quick_job) {
    eventually([&] { return store_up(replica) == 1.0; }, milliseconds(10000));
    httplib::Client client = replica.client(10);
    const std::string location = submit_job(client, request);
    std::string state;
    eventually(
        [&] {
            const auto result = client.Get(location.c_str());
            if (!result || result->status != 200) return false;
            state = json::parse(result->body).value("state", "");
            return state == "succeeded" || state == "failed";
        },
        std::chrono::seconds(30));
    REQUIRE(state == "succeeded");
    return location.substr(std::string("/v1/jobs/").size());
}

struct Timed {
    int status = 0;  // 0: no answer
    double ms = 0;
    std::string body;
};

Timed timed_get(int port, const std::string& path, int timeout_s = 5) {
    httplib::Client client("127.0.0.1", port);
    client.set_connection_timeout(2, 0);
    client.set_read_timeout(timeout_s, 0);
    const auto start = Clock::now();
    const auto result = client.Get(path.c_str());
    return {result ? result->status : 0, ms_since(start), result ? result->body : ""};
}

// `count` concurrent GETs of `path`, each on a connection of its own (so each one occupies an
// HTTP thread of the replica), spread over `ports` in turn.
std::vector<Timed> concurrent_gets(const std::vector<int>& ports, const std::string& path,
                                   int count, int timeout_s = 10) {
    std::vector<Timed> answers(static_cast<std::size_t>(count));
    std::vector<std::thread> threads;
    for (int i = 0; i < count; ++i) {
        threads.emplace_back([&, i] {
            answers[static_cast<std::size_t>(i)] =
                timed_get(ports[static_cast<std::size_t>(i) % ports.size()], path, timeout_s);
        });
    }
    for (std::thread& thread : threads) thread.join();
    return answers;
}

std::map<int, int> statuses(const std::vector<Timed>& answers) {
    std::map<int, int> counts;
    for (const Timed& answer : answers) ++counts[answer.status];
    return counts;
}

std::string describe(const std::map<int, int>& counts) {
    std::ostringstream text;
    for (const auto& [status, n] : counts) text << n << "x" << status << " ";
    return text.str();
}

// The server's own view: connections to `database` by application_name (the service names
// its connections "rollgap/<instance>"), read from pg_stat_activity.
std::map<std::string, int> connections_by_client(const PostgresServer& server,
                                                 const std::string& database) {
    std::map<std::string, int> counts;
    std::istringstream rows(psql(server, "postgres",
                                 "SELECT application_name, count(*) FROM pg_stat_activity "
                                 "WHERE datname = '" +
                                     database + "' GROUP BY 1"));
    std::string row;
    while (std::getline(rows, row)) {
        const auto bar = row.find('|');
        if (bar != std::string::npos) counts[row.substr(0, bar)] = std::atoi(row.c_str() + bar + 1);
    }
    return counts;
}

std::optional<double> store_up(const Replica& replica) {
    const Timed metrics = timed_get(replica.admin_port(), "/metrics");
    if (metrics.status != 200) return std::nullopt;
    return metric_value(metrics.body, "rollgap_store_up");
}

std::size_t occurrences(const std::string& text, const std::string& needle) {
    std::size_t count = 0;
    for (auto at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1))
        ++count;
    return count;
}

}  // namespace

TEST_CASE(
    "store outage: two replicas under rounds of 40 concurrent job polls stay within "
    "--store-connections on a PostgreSQL with max_connections 16") {
    PostgresServer& postgres = shared_postgres();
    TempDir directory("rollgap-bound");
    const std::string dsn = postgres.create_database("bound");
    REQUIRE(!dsn.empty());
    ReplicaOptions options;
    options.environment = {"ROLLGAP_STORE_CONNECTIONS=4"};
    Replica a("a", dsn, directory.path(), options);
    Replica b("b", dsn, directory.path(), options);
    const std::string id = finished_job(a);

    // Sampled from the server's side all through the rounds, a psql at a time (tens of ms
    // each, more on a loaded machine). A pooled connection stays open until it has been idle
    // 30 s, so whatever a replica opened during the rounds is still there at the next sample.
    std::atomic<bool> sampling{true};
    int peak_a = 0, peak_b = 0, samples = 0;
    std::thread sampler([&] {
        while (sampling) {
            const auto counts = connections_by_client(postgres, "bound");
            const auto count = [&](const std::string& name) {
                const auto it = counts.find(name);
                return it == counts.end() ? 0 : it->second;
            };
            peak_a = std::max(peak_a, count("rollgap/a"));
            peak_b = std::max(peak_b, count("rollgap/b"));
            ++samples;
            std::this_thread::sleep_for(milliseconds(5));
        }
    });
    std::map<int, int> all;
    int peak_total = 0;
    bool other_client = true;
    for (int round = 0; round < 3; ++round) {
        for (const auto& [status, n] :
             statuses(concurrent_gets({a.port(), b.port()}, "/v1/jobs/" + id, 40)))
            all[status] += n;
        // Another application of the same server still gets in.
        const std::string psql_command = std::string(postgres_bin) + "/psql -h 127.0.0.1 -p " +
                                         std::to_string(postgres.port()) +
                                         " -U postgres -d postgres -At -c \"SELECT count(*) "
                                         "FROM pg_stat_activity WHERE datname = 'bound'\"";
        FILE* pipe = ::popen((psql_command + " 2>&1").c_str(), "r");
        REQUIRE(pipe != nullptr);
        char buffer[512] = {};
        const std::size_t n = std::fread(buffer, 1, sizeof buffer - 1, pipe);
        other_client = ::pclose(pipe) == 0 && other_client;
        peak_total = std::max(peak_total, std::atoi(std::string(buffer, n).c_str()));
    }
    sampling = false;
    sampler.join();
    MESSAGE("3 rounds of 40 polls on 2 replicas: "
            << describe(all) << "; connections per replica " << peak_a << " and " << peak_b << " ("
            << samples << " samples), in pg_stat_activity " << peak_total);
    CHECK(all[200] == 120);
    CHECK(samples >= 1);
    CHECK(peak_a >= 1);  // the replicas' connections are named, so the sampler sees them
    CHECK(peak_b >= 1);
    CHECK(peak_a <= 4);
    CHECK(peak_b <= 4);
    CHECK(peak_total <= 8);
    CHECK(other_client);
}

TEST_CASE(
    "store outage: after a PostgreSQL restart the first job operations succeed and no computed "
    "chunk is lost") {
    PostgresServer& postgres = shared_postgres();
    const std::string dsn = postgres.create_database("restart");
    REQUIRE(!dsn.empty());
    TempDir directory("rollgap-restart");
    ReplicaOptions options;
    options.environment = {"ROLLGAP_STORE_CONNECTIONS=4"};
    options.chunk_points = 5;
    options.lease = milliseconds(5000);  // longer than the restart: no chunk changes hands
    Replica replica("a", dsn, directory.path(), options);
    CAPTURE(replica.log_text());
    const std::string id = finished_job(replica);
    // Connections in use on every thread that may hold one.
    CHECK(statuses(concurrent_gets({replica.port()}, "/v1/jobs/" + id, 40))[200] == 40);

    REQUIRE(postgres.stop());
    REQUIRE(postgres.start());
    auto after = statuses(concurrent_gets({replica.port()}, "/v1/jobs/" + id, 40));
    MESSAGE("the first 40 polls after a restart: " << describe(after));
    CHECK(after[200] == 40);

    // A sweep whose chunks are computed while the database restarts: every result is stored
    // (retried until the database is back), none is computed again.
    const json sweep = {
        {"analysis", "sweep"},
        {"options",
         {{"parameter", "/lubricant/viscosity_Pa_s"},
          {"range", {{"from", 0.00045}, {"to", 0.0007}, {"count", 60}}},
          {"quantity", "critical_speed"},
          {"critical_speed",
           {{"speed_min_m_per_s", 17}, {"speed_max_m_per_s", 23}, {"relative_tolerance", 0.01}}}}}};
    httplib::Client client = replica.client(10);
    const std::string location = submit_job(client, sweep);
    REQUIRE(eventually(
        [&] {
            const auto result = client.Get(location.c_str());
            return result && result->status == 200 &&
                   json::parse(result->body).value("state", "") == "running";
        },
        std::chrono::seconds(10)));
    REQUIRE(postgres.stop());
    std::this_thread::sleep_for(milliseconds(300));  // chunks finish while it is down
    REQUIRE(postgres.start());
    std::string state;
    eventually(
        [&] {
            const auto result = client.Get(location.c_str());
            if (result && result->status == 200)
                state = json::parse(result->body).value("state", "");
            std::this_thread::sleep_for(milliseconds(20));
            return state == "succeeded" || state == "failed";
        },
        std::chrono::seconds(30));
    CHECK(state == "succeeded");
    const std::string metrics = replica.metrics();
    CHECK(metric_value(metrics, "rollgap_work_items_total", "outcome=\"unstored\"").value_or(0) ==
          0);
    CHECK(metric_value(metrics, "rollgap_work_items_total", "outcome=\"succeeded\"").value_or(0) ==
          1 + 12);
}

TEST_CASE(
    "store outage: a partition: health and metrics answer at once, job routes answer 503 within "
    "the deadline, analyses go on, and the store comes back") {
    PostgresServer& postgres = shared_postgres();
    REQUIRE(!postgres.create_database("partition").empty());
    TcpRelay relay(postgres.port());
    TempDir directory("rollgap-partition");
    ReplicaOptions options;
    options.environment = {"ROLLGAP_STORE_DEADLINE_MS=300", "ROLLGAP_STORE_CONNECTIONS=4"};
    Replica replica(
        "a", "postgresql://postgres@127.0.0.1:" + std::to_string(relay.port()) + "/partition",
        directory.path(), options);
    CAPTURE(replica.log_text());
    const std::string id = finished_job(replica);
    REQUIRE(store_up(replica) == 1.0);

    relay.freeze();
    // Two scrapes pending at once (both admin threads, before the change) ...
    std::vector<Timed> scrapes(2);
    std::vector<std::thread> scrapers;
    for (auto& scrape : scrapes)
        scrapers.emplace_back([&] { scrape = timed_get(replica.admin_port(), "/metrics"); });
    std::this_thread::sleep_for(milliseconds(50));
    // ... and the liveness probe.
    double livez_worst = 0;
    for (int i = 0; i < 5; ++i) {
        const Timed livez = timed_get(replica.admin_port(), "/livez");
        CHECK(livez.status == 200);
        livez_worst = std::max(livez_worst, livez.ms);
    }
    for (std::thread& scraper : scrapers) scraper.join();
    const auto polls = concurrent_gets({replica.port()}, "/v1/jobs/" + id, 40, 5);
    double poll_worst = 0;
    for (const Timed& poll : polls) poll_worst = std::max(poll_worst, poll.ms);
    MESSAGE("partition: /livez worst "
            << livez_worst << " ms, /metrics " << std::max(scrapes[0].ms, scrapes[1].ms)
            << " ms, 40 job polls " << describe(statuses(polls)) << "worst " << poll_worst
            << " ms");
    CHECK(livez_worst < 500);
    for (const Timed& scrape : scrapes) {
        CHECK(scrape.status == 200);
        CHECK(scrape.ms < 500);
    }
    CHECK(statuses(polls)[503] == 40);
    CHECK(poll_worst < 300 + 1000);
    const Timed poll = timed_get(replica.port(), "/v1/jobs/" + id);
    CHECK(poll.status == 503);
    CHECK(json::parse(poll.body, nullptr, false).value("code", "") == "store_unavailable");
    const auto submitted = [&] {
        httplib::Client client = replica.client(5);
        const auto start = Clock::now();
        const auto result = post_json(client, "/v1/jobs", quick_job);
        return Timed{result ? result->status : 0, ms_since(start), result ? result->body : ""};
    }();
    CHECK(submitted.status == 503);
    CHECK(submitted.ms < 300 + 1000);
    // Synchronous analyses never need the store.
    httplib::Client client = replica.client(10);
    const auto analysis =
        post_json(client, "/v1/roll-gap", {{"options", {{"distributions", false}}}});
    REQUIRE(analysis);
    CHECK(analysis->status == 200);
    CHECK(eventually([&] { return store_up(replica) == 0.0; }, milliseconds(5000)));
    const Timed ready = timed_get(replica.admin_port(), "/readyz");
    CHECK(ready.status == 200);
    CHECK(json::parse(ready.body, nullptr, false)["store"]["up"] == false);

    relay.thaw();
    CHECK(eventually([&] { return store_up(replica) == 1.0; }, milliseconds(15000)));
    CHECK(timed_get(replica.port(), "/v1/jobs/" + id).status == 200);
}

TEST_CASE(
    "store outage (sqlite): a file the service cannot write: reads go on, store_up is 0, one "
    "log line") {
    TempDir directory("rollgap-readonly");
    const std::filesystem::path file = directory.path() / "jobs.db";
    const std::string store = "sqlite:" + file.string();
    std::string id;
    {
        Replica writer("writer", store, directory.path());
        id = finished_job(writer);
        REQUIRE(writer.terminate() == 0);
    }
    // The file is root's and read-only; the directory stays writable (SQLite's -wal and -shm).
    std::filesystem::permissions(directory.path(), std::filesystem::perms::all);
    REQUIRE(::chmod(file.c_str(), 0444) == 0);
    for (const char* suffix : {"-wal", "-shm"}) {
        const std::string side = file.string() + suffix;
        if (std::filesystem::exists(side)) REQUIRE(::chmod(side.c_str(), 0666) == 0);
    }
    ReplicaOptions options;
    options.user = "nobody";
    Replica reader("reader", store, directory.path(), options);
    CAPTURE(reader.log_text());

    CHECK(timed_get(reader.port(), "/v1/jobs/" + id).status == 200);
    httplib::Client client = reader.client(5);
    const auto refused = post_json(client, "/v1/jobs", quick_job);
    REQUIRE(refused);
    CHECK(refused->status == 503);
    CHECK(eventually([&] { return store_up(reader) == 0.0; }));
    // Reads that succeed do not turn it up, nor does the log flap over several probes.
    for (int i = 0; i < 6; ++i) {
        CHECK(timed_get(reader.port(), "/v1/jobs/" + id).status == 200);
        CHECK(timed_get(reader.port(), "/v1/jobs").status == 200);
        std::this_thread::sleep_for(milliseconds(400));
        CHECK(store_up(reader) == 0.0);
    }
    const std::string log = reader.log_text();
    CHECK(occurrences(log, "job store unavailable") == 1);
    CHECK(occurrences(log, "job store available again") == 0);
}

TEST_CASE(
    "store outage (sqlite): a file deleted under the service: /readyz says so and a submission "
    "answers 503, not 202") {
    TempDir directory("rollgap-deleted");
    const std::filesystem::path file = directory.path() / "jobs.db";
    Replica replica("a", "sqlite:" + file.string(), directory.path());
    CAPTURE(replica.log_text());
    finished_job(replica);
    REQUIRE(std::filesystem::remove(file));

    httplib::Client client = replica.client(5);
    const auto refused = post_json(client, "/v1/jobs", quick_job);
    REQUIRE(refused);
    CHECK(refused->status == 503);
    CHECK(json::parse(refused->body, nullptr, false).value("code", "") == "store_unavailable");
    std::string detail;
    CHECK(eventually([&] {
        const Timed ready = timed_get(replica.admin_port(), "/readyz");
        const json body = json::parse(ready.body, nullptr, false);
        if (ready.status != 200 || !body.contains("store")) return false;
        detail = body["store"].value("detail", "");
        return body["store"]["up"] == false && detail.find("deleted or moved") != std::string::npos;
    }));
    CAPTURE(detail);
    CHECK(store_up(replica) == 0.0);
}
