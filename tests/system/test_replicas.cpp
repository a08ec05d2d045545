// Replicas sharing one PostgreSQL job store, as separate `rollgap serve` processes (the built
// program) started by the test, directly and behind nginx with the product's front proxy
// configuration in plain round-robin: a job is answered by any replica, a sweep's chunks are
// claimed by both and assemble to the single-process result, a replica killed with SIGKILL loses
// its work to the other after its lease, and a database that goes away stops only the job
// routes (tests/support/replicas.h; docs/job-store.md).

#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/replicas.h"

using namespace rollgap::test;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

// A critical-speed sweep of `count` lubricant viscosities with a coarse search (speeds 17-23
// m/s, 1 % tolerance): the cheapest real sweep we found (every point is a stability search that
// finds its critical speed, 22.8 down to 17.2 m/s, about 7 ms of CPU each on this machine;
// an amplitude sweep even with a 0.2 s window costs five times as much).
json sweep_request(int count) {
    return {
        {"analysis", "sweep"},
        {"options",
         {{"parameter", "/lubricant/viscosity_Pa_s"},
          {"range", {{"from", 0.00045}, {"to", 0.0007}, {"count", count}}},
          {"quantity", "critical_speed"},
          {"critical_speed",
           {{"speed_min_m_per_s", 17}, {"speed_max_m_per_s", 23}, {"relative_tolerance", 0.01}}}}}};
}

// What `rollgap run` prints for `request`: the single-process result, computed without any
// service or store.
json single_process_result(const std::filesystem::path& directory, const json& request) {
    const auto file = directory / "request.json";
    {
        std::ofstream out(file);
        out << request.dump();
    }
    const std::string output = command_output(rollgap_program().string() + " run " + file.string());
    return json::parse(output);
}

// POST /v1/jobs (202 with the job's Location); the new job's id.
std::string submit(httplib::Client& client, const json& request) {
    return submit_job(client, request).substr(std::string("/v1/jobs/").size());
}

struct Answer {
    int status = 0;
    json body;
};

Answer get_job(httplib::Client& client, const std::string& id) {
    const auto result = client.Get(("/v1/jobs/" + id).c_str());
    REQUIRE(result);
    return {result->status, json::parse(result->body, nullptr, false)};
}

bool finished(const json& job) {
    const std::string state = job.value("state", "");
    return state == "succeeded" || state == "failed" || state == "cancelled";
}

// Polls the job through `client` until it is finished or `timeout` passes; its last document.
// (Every 20 ms, not as fast as poll_until_finished: a running sweep's document carries its
// partial result, read from the store, and polling must not slow the replicas it measures.)
json wait_finished(httplib::Client& client, const std::string& id,
                   std::chrono::milliseconds timeout = std::chrono::seconds(60)) {
    json last;
    eventually(
        [&] {
            const Answer answer = get_job(client, id);
            if (answer.status == 200) last = answer.body;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            return answer.status == 200 && finished(last);
        },
        timeout);
    return last;
}

// How many of `path`'s requests a replica's log records (one line per request).
std::size_t requests_logged(const Replica& replica, const std::string& method,
                            const std::string& path) {
    const std::string log = replica.log_text();
    const std::string needle = "method=" + method + " route=";
    std::size_t count = 0;
    for (std::size_t at = log.find(needle); at != std::string::npos;
         at = log.find(needle, at + 1)) {
        const std::size_t end = log.find('\n', at);
        if (log.substr(at, end - at).find(" path=" + path + " ") != std::string::npos) ++count;
    }
    return count;
}

// The instance that completed each finished chunk of job `id`, from the store itself.
std::map<std::string, int> chunks_by_owner(ReplicaSet& replicas, const std::string& id) {
    std::map<std::string, int> owners;
    const std::string rows =
        psql(replicas.postgres(), "replicas",
             "SELECT lease_owner, count(*) FROM chunks WHERE job_id = '" + id +
                 "' AND state = 'done' GROUP BY lease_owner ORDER BY lease_owner");
    std::istringstream lines(rows);
    std::string line;
    while (std::getline(lines, line)) {
        const std::size_t bar = line.find('|');
        if (bar != std::string::npos) owners[line.substr(0, bar)] = std::stoi(line.substr(bar + 1));
    }
    return owners;
}

// The sweep's points are the requested values, each once and in order (the reference's values
// are distinct), and the whole document equals the single-process one.
void check_same_sweep(const json& job, const json& reference, int count) {
    REQUIRE(job["state"] == "succeeded");
    const json& points = job["result"]["result"]["points"];
    REQUIRE(points.is_array());
    CHECK(points.size() == static_cast<std::size_t>(count));
    std::set<double> values;
    for (const json& point : reference["result"]["points"])
        values.insert(point["value_Pa_s"].get<double>());
    CHECK(values.size() == static_cast<std::size_t>(count));
    CHECK(job["result"] == reference);
}

}  // namespace

TEST_CASE(
    "replicas: a job submitted to one replica is polled, cancelled and deleted on the other") {
    ReplicaSet replicas(2);
    httplib::Client a = replicas[0].client();
    httplib::Client b = replicas[1].client();
    CAPTURE(replicas.logs());

    // A sweep long enough to be cancelled while it runs (1000 points, the default search).
    json request = sweep_request(1000);
    request["options"].erase("critical_speed");
    const std::string id = submit(a, request);

    const Answer seen = get_job(b, id);
    CHECK(seen.status == 200);
    CHECK(seen.body["id"] == id);
    CHECK(seen.body["analysis"] == "sweep");

    REQUIRE(eventually([&] { return get_job(b, id).body.value("state", "") == "running"; },
                       std::chrono::seconds(20)));
    const auto cancel = b.Delete(("/v1/jobs/" + id).c_str());
    REQUIRE(cancel);
    CHECK(cancel->status == 200);

    // The cancel reached the worker through the store, wherever it runs.
    const json cancelled = wait_finished(a, id, std::chrono::seconds(20));
    CHECK(cancelled["state"] == "cancelled");
    CHECK(eventually(
        [&] {
            return metric_value(replicas[0].metrics(), "rollgap_workers_busy") == 0.0 &&
                   metric_value(replicas[1].metrics(), "rollgap_workers_busy") == 0.0;
        },
        std::chrono::seconds(10)));

    const auto deleted = b.Delete(("/v1/jobs/" + id).c_str());
    REQUIRE(deleted);
    CHECK(deleted->status == 200);
    CHECK(get_job(a, id).status == 404);
    CHECK(get_job(b, id).status == 404);
}

TEST_CASE("replicas: behind nginx in round-robin, one job's requests reach both replicas") {
    ReplicaSet replicas(2, {}, true);
    httplib::Client proxy = replicas.proxy_client();
    CAPTURE(replicas.logs());

    const std::string id = submit(proxy, sweep_request(20));
    const json done = wait_finished(proxy, id);
    CHECK(done["state"] == "succeeded");
    // Several polls in a row: round-robin sends them to each replica in turn.
    for (int i = 0; i < 4; ++i) {
        const Answer answer = get_job(proxy, id);
        CHECK(answer.status == 200);
        CHECK(answer.body["state"] == "succeeded");
    }
    const std::string path = "/v1/jobs/" + id;
    CHECK(eventually([&] {
        return requests_logged(replicas[0], "GET", path) >= 2 &&
               requests_logged(replicas[1], "GET", path) >= 2;
    }));

    // A second job, cancelled and deleted through the proxy while it runs.
    json long_request = sweep_request(1000);
    long_request["options"].erase("critical_speed");
    const std::string long_id = submit(proxy, long_request);
    REQUIRE(eventually([&] { return get_job(proxy, long_id).body.value("state", "") == "running"; },
                       std::chrono::seconds(20)));
    const auto cancel = proxy.Delete(("/v1/jobs/" + long_id).c_str());
    REQUIRE(cancel);
    CHECK(cancel->status == 200);
    CHECK(wait_finished(proxy, long_id, std::chrono::seconds(20))["state"] == "cancelled");
    const auto deleted = proxy.Delete(("/v1/jobs/" + long_id).c_str());
    REQUIRE(deleted);
    CHECK(deleted->status == 200);
    for (int i = 0; i < 2; ++i) CHECK(get_job(proxy, long_id).status == 404);
    const std::string long_path = "/v1/jobs/" + long_id;
    CHECK(eventually([&] {
        return requests_logged(replicas[0], "GET", long_path) >= 1 &&
               requests_logged(replicas[1], "GET", long_path) >= 1;
    }));
}

// Two replicas with chunks of `chunk` points and lease `lease`, and the single-process result
// of the 200-point sweep they are given.
struct SweepReplicas {
    static constexpr int points = 200;
    static constexpr int chunk = 10;
    ReplicaSet replicas;
    json request = sweep_request(points);
    json reference;

    explicit SweepReplicas(std::chrono::milliseconds lease) : replicas(2, options(lease)) {
        reference = single_process_result(replicas.directory(), request);
    }
    static ReplicaOptions options(std::chrono::milliseconds lease) {
        ReplicaOptions options;
        options.lease = lease;
        options.chunk_points = chunk;
        return options;
    }
    // The sweep submitted to the second replica, once a few of its chunks are done (the
    // replicas hold chunks then); its id.
    std::string submit_and_wait_under_way() {
        httplib::Client b = replicas[1].client();
        const std::string id = submit(b, request);
        REQUIRE(eventually([&] { return get_job(b, id).body.value("points_done", 0) >= 3 * chunk; },
                           std::chrono::seconds(30)));
        const json running = get_job(b, id).body;
        REQUIRE(running["state"] == "running");
        // The points finished so far, whichever replica computed them, are the single-process
        // run's points at the same indices, marked partial.
        const json& partial = running["partial_result"];
        CHECK(partial["partial"] == true);
        CHECK(partial["points_total"] == points);
        // (Read after the job's row: a chunk may have finished in between.)
        CHECK(partial["points_done"] >= running["points_done"]);
        REQUIRE(partial["points"].is_array());
        CHECK(partial["points"].size() == partial["points_done"].get<std::size_t>());
        for (const json& entry : partial["points"]) {
            const std::size_t index = entry["index"];
            REQUIRE(index < static_cast<std::size_t>(points));
            CHECK(entry["point"] == reference["result"]["points"][index]);
        }
        return id;
    }
    // Chunks of the job completed, by all replicas together.
    int chunks_done(const std::string& id) {
        int total = 0;
        for (const auto& [owner, chunks] : chunks_by_owner(replicas, id)) total += chunks;
        return total;
    }
};

long long elapsed_ms(Clock::time_point since) {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - since).count();
}

TEST_CASE(
    "replicas: a 200-point sweep is claimed by both replicas and equals the single-process run") {
    SweepReplicas sweep(std::chrono::milliseconds(1500));
    ReplicaSet& replicas = sweep.replicas;
    CAPTURE(replicas.logs());

    httplib::Client a = replicas[0].client();
    const std::string id = submit(a, sweep.request);
    httplib::Client b = replicas[1].client();
    check_same_sweep(wait_finished(b, id), sweep.reference, sweep.points);

    // 20 chunks of 10 points, each completed once; both replicas completed some, as the store
    // records (the lease holder that completed each chunk) and each replica counts.
    const auto owners = chunks_by_owner(replicas, id);
    for (const auto& [owner, chunks] : owners)
        MESSAGE(owner << " completed " << chunks << " chunks");
    CHECK(sweep.chunks_done(id) == sweep.points / sweep.chunk);
    CHECK(owners.size() == 2);
    const auto succeeded = [&](std::size_t i) {
        return metric_value(replicas[i].metrics(), "rollgap_work_items_total",
                            "outcome=\"succeeded\"")
            .value_or(0.0);
    };
    CHECK(succeeded(0) > 0);
    CHECK(succeeded(1) > 0);
    CHECK(succeeded(0) + succeeded(1) == sweep.points / sweep.chunk);
}

TEST_CASE("replicas: kill -9 of a replica running a sweep: the other finishes it after the lease") {
    SweepReplicas sweep(std::chrono::milliseconds(1500));
    ReplicaSet& replicas = sweep.replicas;
    CAPTURE(replicas.logs());
    const std::string id = sweep.submit_and_wait_under_way();
    // Killed while it holds a chunk: between two chunks a replica holds nothing, and a kill then
    // would test nothing. Frozen (SIGSTOP) so that its chunk cannot finish while the store is
    // read; thawed and tried again when it held none at that instant.
    const std::string held_query = "SELECT idx, lease_until_ms FROM chunks WHERE job_id = '" + id +
                                   "' AND lease_owner = 'a' AND state = 'running'";
    std::string held;
    const auto give_up = Clock::now() + std::chrono::seconds(30);
    while (held.empty() && Clock::now() < give_up) {
        ::kill(replicas[0].pid(), SIGSTOP);
        held = psql(replicas.postgres(), "replicas", held_query);
        if (held.empty()) {
            ::kill(replicas[0].pid(), SIGCONT);
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    }
    // What the dead replica held: chunks leased to it, and until when.
    CAPTURE(held);
    REQUIRE_MESSAGE(!held.empty(), "replica a never held a chunk of the sweep");
    const auto killed_at = Clock::now();
    replicas[0].kill9();

    httplib::Client b = replicas[1].client();
    const json done = wait_finished(b, id, std::chrono::seconds(60));
    MESSAGE("finished " << elapsed_ms(killed_at)
                        << " ms after the kill; the dead replica held (idx|lease_until_ms): "
                        << held);
    check_same_sweep(done, sweep.reference, sweep.points);
    // Every chunk completed exactly once: by the dead replica before it died or by the survivor.
    CHECK(sweep.chunks_done(id) == sweep.points / sweep.chunk);
    // The chunks the dead replica held were completed by the survivor, and the job finished
    // only after their lease ran out.
    std::istringstream rows(held);
    std::string row;
    int taken_over = 0;
    while (std::getline(rows, row)) {
        const std::size_t bar = row.find('|');
        if (bar == std::string::npos) continue;
        const std::string idx = row.substr(0, bar);
        const long long lease_until = std::stoll(row.substr(bar + 1));
        const std::string after =
            psql(replicas.postgres(), "replicas",
                 "SELECT c.lease_owner, j.finished_ms FROM chunks c JOIN jobs j ON j.id = c.job_id "
                 "WHERE c.job_id = '" +
                     id + "' AND c.idx = " + idx);
        CAPTURE(after);
        CHECK(after.rfind("b|", 0) == 0);
        CHECK(std::stoll(after.substr(after.find('|') + 1)) >= lease_until);
        ++taken_over;
    }
    CHECK(taken_over >= 1);
}

TEST_CASE("replicas: a draining replica gives its chunks back and the other finishes the sweep") {
    // A lease far longer than the test: the survivor can only finish quickly if the draining
    // replica gave its chunks back instead of letting their leases run out.
    constexpr auto lease = std::chrono::milliseconds(60000);
    SweepReplicas sweep(lease);
    ReplicaSet& replicas = sweep.replicas;
    CAPTURE(replicas.logs());
    const std::string id = sweep.submit_and_wait_under_way();
    const auto signalled_at = Clock::now();
    const std::optional<int> status = replicas[0].terminate();
    REQUIRE(status);
    CHECK(WIFEXITED(*status));
    CHECK(WEXITSTATUS(*status) == 0);
    httplib::Client b = replicas[1].client();
    const json done = wait_finished(b, id, std::chrono::seconds(40));
    const auto finished_after = elapsed_ms(signalled_at);
    MESSAGE("SIGTERM: the sweep finished " << finished_after
                                           << " ms after the signal (lease 60 s)");
    check_same_sweep(done, sweep.reference, sweep.points);
    CHECK(sweep.chunks_done(id) == sweep.points / sweep.chunk);
    CHECK(finished_after < lease.count());
}

TEST_CASE(
    "replicas: PostgreSQL stopped: analyses go on, job routes answer 503, and service resumes") {
    ReplicaSet replicas(1);
    Replica& replica = replicas[0];
    httplib::Client client = replica.client();
    CAPTURE(replicas.logs());

    const json analysis_body = {{"options", {{"distributions", false}}}};
    json quick = analysis_body;
    quick["analysis"] = "roll_gap";
    const std::string before = submit(client, quick);
    REQUIRE(wait_finished(client, before)["state"] == "succeeded");
    CHECK(metric_value(replica.metrics(), "rollgap_store_up") == 1.0);

    REQUIRE(replicas.postgres().stop());

    // Synchronous analyses without a stored base never touch the store.
    const auto analysis = post_json(client, "/v1/roll-gap", analysis_body);
    REQUIRE(analysis);
    CHECK(analysis->status == 200);
    const auto ready = client.Get("/readyz");
    REQUIRE(ready);
    CHECK(ready->status == 200);

    const auto check_unavailable = [](const httplib::Result& result) {
        REQUIRE(result);
        CAPTURE(result->body);
        CHECK(result->status == 503);
        CHECK(result->get_header_value("Content-Type") == "application/problem+json");
        CHECK_FALSE(result->get_header_value("Retry-After").empty());
        CHECK(json::parse(result->body, nullptr, false).value("code", "") == "store_unavailable");
    };
    check_unavailable(post_json(client, "/v1/jobs", quick));
    check_unavailable(client.Get(("/v1/jobs/" + before).c_str()));
    check_unavailable(client.Get("/v1/jobs"));
    CHECK(metric_value(replica.metrics(), "rollgap_store_up") == 0.0);
    CHECK(replica.log_text().find("job store unavailable") != std::string::npos);
    // Still answering analyses while the store is down.
    const auto again = post_json(client, "/v1/roll-gap", analysis_body);
    REQUIRE(again);
    CHECK(again->status == 200);

    REQUIRE(replicas.postgres().start());
    // The job of before the outage is there; the refused submission left nothing behind.
    CHECK(eventually([&] { return get_job(client, before).status == 200; },
                     std::chrono::seconds(15)));
    CHECK(get_job(client, before).body["state"] == "succeeded");
    const auto list = client.Get("/v1/jobs?limit=100");
    REQUIRE(list);
    CHECK(list->status == 200);
    const json jobs = json::parse(list->body)["jobs"];
    REQUIRE(jobs.size() == 1);
    CHECK(jobs[0]["id"] == before);
    const std::string after = submit(client, quick);
    CHECK(wait_finished(client, after)["state"] == "succeeded");
    CHECK(metric_value(replica.metrics(), "rollgap_store_up") == 1.0);
    CHECK(replica.log_text().find("job store available again") != std::string::npos);
}

TEST_CASE(
    "replicas: a batch's coils are chunked over both replicas and through nginx's own limit") {
    // Two replicas on one PostgreSQL store behind the product's nginx configuration.
    ReplicaOptions options;
    options.chunk_points = 10;
    ReplicaSet replicas(2, options, true);
    CAPTURE(replicas.logs());

    // 200 coils, each a speed limit with the sweep's coarse search at its own viscosity (about
    // 7 ms of CPU a coil): 20 chunks of 10 coils.
    json items = json::array();
    for (int i = 0; i < 200; ++i) {
        items.push_back(
            {{"label", "coil-" + std::to_string(i)},
             {"scenario", {{"lubricant", {{"viscosity_Pa_s", 4.5e-4 + 1.25e-6 * i}}}}}});
    }
    const json request = {{"analysis", "batch"},
                          {"options",
                           {{"analysis", "speed_limit"},
                            {"options",
                             {{"speed_min_m_per_s", 17},
                              {"speed_max_m_per_s", 23},
                              {"relative_tolerance", 0.01},
                              {"max_roll_force_kN", 7000}}},
                            {"items", items}}}};
    const json reference = single_process_result(replicas.directory(), request);
    httplib::Client a = replicas[0].client();
    const auto posted = post_json(a, "/v1/batches", {{"options", request["options"]}});
    REQUIRE(posted);
    REQUIRE(posted->status == 202);
    const std::string id = json::parse(posted->body)["id"];
    httplib::Client b = replicas[1].client();
    const json job = wait_finished(b, id);
    REQUIRE(job["state"] == "succeeded");
    // Byte for byte the single process's rows, whichever replica computed which chunk.
    CHECK(job["result"] == reference);
    CHECK(job["result"]["result"]["succeeded"] == 200);
    const auto owners = chunks_by_owner(replicas, id);
    for (const auto& [owner, chunks] : owners)
        MESSAGE(owner << " completed " << chunks << " chunks of the batch");
    int chunks = 0;
    for (const auto& [owner, done] : owners) chunks += done;
    CHECK(chunks == 20);
    CHECK(owners.size() == 2);

    // Through nginx: a batch above the 1 MiB of every other route (1,000 roll gaps, each a whole
    // stand document) is accepted at /v1/batches and refused (413, as a problem) at /v1/jobs.
    httplib::Client proxy = replicas.proxy_client();
    const json stand = json::parse(proxy.Get("/v1/scenarios/default")->body);
    json large = json::array();
    for (int i = 0; i < 1000; ++i)
        large.push_back({{"label", "coil-" + std::to_string(i)}, {"scenario", stand}});
    const json options_large = {{"analysis", "roll_gap"}, {"items", large}};
    const std::string body = json{{"options", options_large}}.dump();
    REQUIRE(body.size() > 1048576);
    const auto through = proxy.Post("/v1/batches", body, "application/json");
    REQUIRE(through);
    CAPTURE(through->body.substr(0, 300));
    CHECK(through->status == 202);
    // The same length declared to /v1/jobs: nginx answers 413 (a problem) without reading it.
    const std::string as_job = raw_exchange(
        replicas.proxy_port(),
        "POST /v1/jobs HTTP/1.1\r\nHost: localhost\r\nContent-Type: application/json\r\n"
        "Content-Length: " +
            std::to_string(body.size()) + "\r\n\r\n{");
    CHECK(raw_status(as_job) == 413);
    CHECK(as_job.find("application/problem+json") != std::string::npos);
    const json large_job =
        wait_finished(proxy, json::parse(through->body)["id"], std::chrono::seconds(120));
    CHECK(large_job["state"] == "succeeded");
    CHECK(large_job["result"]["result"]["items_total"] == 1000);
}
