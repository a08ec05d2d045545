// Completion callbacks on real servers with a real local receiver (an HTTP server the test
// starts): a finished job's document reaches the receiver signed over "timestamp.body" with
// the operator's secret and a delivery id; a receiver that is down and then fails is retried
// with backoff until it takes the delivery, under one id and one body; attempts run out into
// `failed`; two replicas on one store deliver each callback once; URLs outside the allowed
// prefixes are refused before anything is stored.

#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "service/webhooks.h"
#include "support/http_test.h"
#include "support/loopback_port.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;

namespace webhooks_http_test {

constexpr const char* secret = "test-webhook-secret-0123456789";

struct Received {
    std::string path, query_line, content_type, delivery, event, timestamp, signature, body;
};

// A callback receiver on 127.0.0.1:`port`: records every request; answers each with the next
// of `statuses` (the last one repeats).
class Receiver {
public:
    Receiver(int port, std::vector<int> statuses) : statuses_(std::move(statuses)) {
        server_.Post(".*", [this](const httplib::Request& request, httplib::Response& response) {
            std::lock_guard lock(mutex_);
            Received r;
            r.path = request.path;
            r.query_line = request.get_param_value("line");
            r.content_type = request.get_header_value("Content-Type");
            r.delivery = request.get_header_value("Rollgap-Delivery");
            r.event = request.get_header_value("Rollgap-Event");
            r.timestamp = request.get_header_value("Rollgap-Timestamp");
            r.signature = request.get_header_value("Rollgap-Signature");
            r.body = request.body;
            received_.push_back(std::move(r));
            const std::size_t i = std::min(received_.size(), statuses_.size()) - 1;
            response.status = statuses_[i];
            response.set_content("{}", "application/json");
        });
        REQUIRE(server_.bind_to_port("127.0.0.1", port));
        thread_ = std::thread([this] { server_.listen_after_bind(); });
        REQUIRE(eventually([this] { return server_.is_running(); }));
    }
    ~Receiver() {
        server_.stop();
        if (thread_.joinable()) thread_.join();
    }
    std::vector<Received> received() {
        std::lock_guard lock(mutex_);
        return received_;
    }
    std::size_t count() { return received().size(); }

private:
    httplib::Server server_;
    std::vector<int> statuses_;
    std::mutex mutex_;
    std::vector<Received> received_;
    std::thread thread_;
};

service::ServerConfig webhook_config(int receiver_port) {
    service::ServerConfig config = test_config();
    config.webhook_allow = {*service::parse_webhook_url(
        "http://127.0.0.1:" + std::to_string(receiver_port) + "/hooks")};
    config.webhook_secret = secret;
    config.webhook_backoff = std::chrono::milliseconds(100);
    return config;
}

std::string hook_url(int port, const std::string& rest = "/hooks/rollgap?line=3") {
    return "http://127.0.0.1:" + std::to_string(port) + rest;
}

// The receiver's check: the signature is the HMAC of "<timestamp>.<body>" under the secret.
bool signed_by_secret(const Received& r) {
    return r.signature == "v1=" + service::hmac_sha256_hex(secret, r.timestamp + "." + r.body);
}

// The process logger's lines while it lives (the deliverer logs there, not in the request log).
class ProcessLog {
public:
    ProcessLog() {
        spdlog::set_default_logger(std::make_shared<spdlog::logger>("webhooks", sink_));
    }
    ~ProcessLog() { spdlog::set_default_logger(previous_); }
    ProcessLog(const ProcessLog&) = delete;
    ProcessLog& operator=(const ProcessLog&) = delete;
    std::string text() { return sink_->text(); }

private:
    std::shared_ptr<CapturingSink> sink_ = std::make_shared<CapturingSink>();
    std::shared_ptr<spdlog::logger> previous_ = spdlog::default_logger();
};

json job_at(httplib::Client& client, const std::string& location) {
    const auto answer = client.Get(location.c_str());
    REQUIRE(answer);
    REQUIRE(answer->status == 200);
    return json::parse(answer->body);
}

}  // namespace webhooks_http_test

namespace wht = webhooks_http_test;

TEST_CASE("callbacks: a finished job is announced to a real receiver, signed, once") {
    const int port = free_loopback_port();
    wht::Receiver receiver(port, {204});
    wht::ProcessLog log;
    TestServer server(wht::webhook_config(port));
    auto client = server.client();
    const std::string location = submit_job(client, {{"analysis", "roll_gap"},
                                                     {"labels", {{"coil", "C-4711"}}},
                                                     {"callback_url", wht::hook_url(port)}});
    REQUIRE(eventually([&] { return receiver.count() == 1; }, std::chrono::milliseconds(15000)));
    const wht::Received got = receiver.received().at(0);
    CHECK(got.path == "/hooks/rollgap");
    CHECK(got.query_line == "3");
    CHECK(got.content_type == "application/json");
    CHECK(got.event == "job.finished");
    CHECK(wht::signed_by_secret(got));
    const auto now_s = std::chrono::duration_cast<std::chrono::seconds>(
                           std::chrono::system_clock::now().time_since_epoch())
                           .count();
    CHECK(std::abs(std::stoll(got.timestamp) - now_s) < 60);
    const json body = json::parse(got.body);
    CHECK(body["event"] == "job.finished");
    CHECK(body["delivery_id"] == got.delivery);
    CHECK("/v1/jobs/" + body["job"]["id"].get<std::string>() == location);
    CHECK(body["job"]["state"] == "succeeded");
    CHECK(body["job"]["labels"]["coil"] == "C-4711");
    CHECK_FALSE(body["job"].contains("result"));  // the summary: the result is a GET away
    REQUIRE(eventually(
        [&] { return wht::job_at(client, location)["callback"]["state"] == "delivered"; }));
    const json job = wht::job_at(client, location);
    // shown without its query (a receiver's token rides there): here and in the callback body
    CHECK(job["callback_url"] == wht::hook_url(port, "/hooks/rollgap?…"));
    CHECK(body["job"]["callback_url"] == wht::hook_url(port, "/hooks/rollgap?…"));
    CHECK(got.body.find("line=3") == std::string::npos);
    CHECK(job["callback"]["attempts"] == 1);
    CHECK_FALSE(job["callback"].contains("last_error"));
    // a tampered body does not verify under the same signature
    wht::Received forged = got;
    forged.body.replace(forged.body.find("succeeded"), 9, "failed\"  ");
    CHECK_FALSE(wht::signed_by_secret(forged));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    CHECK(receiver.count() == 1);  // delivered once
    // the log names the receiver's origin, never its path or query
    const std::string logged = log.text();
    CAPTURE(logged);
    CHECK(logged.find("callback delivered delivery=" + got.delivery) != std::string::npos);
    CHECK(logged.find("to=http://127.0.0.1:" + std::to_string(port)) != std::string::npos);
    CHECK(logged.find("/hooks") == std::string::npos);
    CHECK(logged.find("line=3") == std::string::npos);
}

TEST_CASE("callbacks: a receiver down, then failing, then back gets the delivery, one id") {
    const int port = free_loopback_port();
    TestServer server(wht::webhook_config(port));
    auto client = server.client();
    const std::string location = submit_job(
        client, {{"analysis", "roll_gap"}, {"callback_url", wht::hook_url(port, "/hooks/")}});
    // nobody listens: attempts fail and are retried with backoff
    REQUIRE(eventually(
        [&] {
            const json job = wht::job_at(client, location);
            return job["state"] == "succeeded" && job["callback"]["attempts"].get<int>() >= 2;
        },
        std::chrono::milliseconds(15000)));
    const json waiting = wht::job_at(client, location);
    CHECK(waiting["callback"]["state"] == "pending");
    CAPTURE(waiting.dump());
    CHECK_FALSE(waiting["callback"]["last_error"].get<std::string>().empty());
    // the receiver comes up, answers 500 once, then 200
    wht::Receiver receiver(port, {500, 200});
    REQUIRE(eventually(
        [&] { return wht::job_at(client, location)["callback"]["state"] == "delivered"; },
        std::chrono::milliseconds(15000)));
    const auto got = receiver.received();
    REQUIRE(got.size() == 2);
    CHECK(got[0].delivery == got[1].delivery);  // one delivery, attempted twice
    CHECK(got[0].body == got[1].body);          // the same bytes
    CHECK(wht::signed_by_secret(got[0]));
    CHECK(wht::signed_by_secret(got[1]));
    CHECK(wht::job_at(client, location)["callback"]["attempts"].get<int>() >= 4);
}

TEST_CASE("callbacks: attempts run out into failed, with the last error") {
    const int port = free_loopback_port();
    service::ServerConfig config = wht::webhook_config(port);
    config.webhook_max_attempts = 2;
    config.webhook_backoff = std::chrono::milliseconds(50);
    wht::ProcessLog log;
    TestServer server(config);
    auto client = server.client();
    const std::string location =
        submit_job(client, {{"analysis", "roll_gap"}, {"callback_url", wht::hook_url(port)}});
    REQUIRE(
        eventually([&] { return wht::job_at(client, location)["callback"]["state"] == "failed"; },
                   std::chrono::milliseconds(15000)));
    const json job = wht::job_at(client, location);
    CHECK(job["callback"]["attempts"] == 2);
    CHECK(job["callback"]["last_error"] == "could not connect");
    CHECK(log.text().find("callback failed") != std::string::npos);
}

namespace webhooks_http_test {

// A receiver that answers 200 at once and then dribbles its body, a byte every 200 ms for 40 s:
// every read gets a byte well within the client's per-read timeout (5 s).
class Dribbler {
public:
    explicit Dribbler(int port) {
        server_.Post(".*", [this](const httplib::Request&, httplib::Response& response) {
            ++calls;
            response.set_chunked_content_provider(
                "application/json", [this](std::size_t, httplib::DataSink& sink) {
                    for (int i = 0; i < 200 && !done_; ++i) {
                        if (!sink.write(" ", 1)) return false;
                        std::this_thread::sleep_for(std::chrono::milliseconds(200));
                    }
                    sink.done();
                    return true;
                });
        });
        REQUIRE(server_.bind_to_port("127.0.0.1", port));
        thread_ = std::thread([this] { server_.listen_after_bind(); });
        REQUIRE(eventually([this] { return server_.is_running(); }));
    }
    ~Dribbler() {
        done_ = true;
        server_.stop();
        if (thread_.joinable()) thread_.join();
    }
    Dribbler(const Dribbler&) = delete;
    Dribbler& operator=(const Dribbler&) = delete;
    std::atomic<int> calls{0};

private:
    std::atomic<bool> done_{false};
    httplib::Server server_;
    std::thread thread_;
};

}  // namespace webhooks_http_test

TEST_CASE("callbacks: a receiver that dribbles its answer is cut at --webhook-timeout-ms") {
    const int port = free_loopback_port();
    wht::Dribbler receiver(port);
    service::ServerConfig config = wht::webhook_config(port);
    config.webhook_timeout = std::chrono::milliseconds(1000);
    config.webhook_max_attempts = 2;
    config.webhook_backoff = std::chrono::milliseconds(50);
    TestServer server(config);
    auto client = server.client();
    const auto started = std::chrono::steady_clock::now();
    const std::string location =
        submit_job(client, {{"analysis", "roll_gap"}, {"callback_url", wht::hook_url(port)}});
    REQUIRE(
        eventually([&] { return wht::job_at(client, location)["callback"]["state"] == "failed"; },
                   std::chrono::milliseconds(20000)));
    // Two attempts, each cut after 1 s: not the 40 s a dribbled answer would hold each (and
    // the 30 s lease would have let another replica attempt meanwhile).
    const auto took = std::chrono::steady_clock::now() - started;
    MESSAGE("two attempts cut in " << std::chrono::duration<double>(took).count() << " s");
    CHECK(took < std::chrono::seconds(20));
    const json job = wht::job_at(client, location);
    CHECK(job["callback"]["attempts"] == 2);
    CHECK(receiver.calls == 2);
    CAPTURE(job.dump());
    CHECK(job["callback"]["last_error"].get<std::string>().find("--webhook-timeout-ms") !=
          std::string::npos);
}

TEST_CASE("callbacks: two replicas on one store deliver each callback once") {
    const int port = free_loopback_port();
    wht::Receiver receiver(port, {200});
    service::ServerConfig a = wht::webhook_config(port);
    service::ServerConfig b = wht::webhook_config(port);
    b.store = a.store;
    b.instance = "test-b";
    TestServer first(a);
    TestServer second(b);
    auto client_a = first.client();
    auto client_b = second.client();
    std::vector<std::string> locations;
    for (int i = 0; i < 6; ++i) {
        auto& client = i % 2 == 0 ? client_a : client_b;
        locations.push_back(submit_job(client, {{"analysis", "roll_gap"},
                                                {"labels", {{"coil", "C-" + std::to_string(i)}}},
                                                {"callback_url", wht::hook_url(port)}}));
    }
    REQUIRE(eventually(
        [&] {
            for (const auto& location : locations)
                if (wht::job_at(client_a, location)["callback"]["state"] != "delivered")
                    return false;
            return true;
        },
        std::chrono::milliseconds(20000)));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    const auto got = receiver.received();
    CHECK(got.size() == locations.size());
    std::set<std::string> deliveries, jobs;
    for (const auto& r : got) {
        deliveries.insert(r.delivery);
        jobs.insert(json::parse(r.body)["job"]["id"].get<std::string>());
    }
    CHECK(deliveries.size() == locations.size());
    CHECK(jobs.size() == locations.size());
}

TEST_CASE(
    "callbacks: a delivery whose prefix the operator took off the list is given up, not sent") {
    const int port = free_loopback_port();
    service::ServerConfig before = wht::webhook_config(port);
    before.webhook_backoff = std::chrono::milliseconds(200);
    std::string location;
    {
        // the receiver is down: the first attempt fails and the delivery waits in the store
        TestServer first(before);
        auto client = first.client();
        location =
            submit_job(client, {{"analysis", "roll_gap"}, {"callback_url", wht::hook_url(port)}});
        REQUIRE(eventually(
            [&] { return wht::job_at(client, location)["callback"]["attempts"].get<int>() >= 1; }));
    }
    // restarted on the same store with another prefix, the receiver up: nothing reaches it
    wht::Receiver receiver(port, {200});
    service::ServerConfig after = wht::webhook_config(port);
    after.store = before.store;
    after.webhook_allow = {
        *service::parse_webhook_url("http://127.0.0.1:" + std::to_string(port) + "/other")};
    TestServer second(after);
    auto client = second.client();
    REQUIRE(
        eventually([&] { return wht::job_at(client, location)["callback"]["state"] == "failed"; },
                   std::chrono::milliseconds(15000)));
    CHECK(wht::job_at(client, location)["callback"]["last_error"].get<std::string>().find(
              "no longer under a prefix") != std::string::npos);
    CHECK(receiver.count() == 0);
}

TEST_CASE("callbacks: a URL outside the allowed prefixes is a 422 and nothing is stored") {
    const int port = free_loopback_port();
    TestServer server(wht::webhook_config(port));
    auto client = server.client();
    for (const std::string& url :
         {wht::hook_url(port, "/other"), wht::hook_url(port, "/hooks-evil"),
          wht::hook_url(port + 1 == 65536 ? 1 : port + 1, "/hooks"),
          "http://127.0.0.1:" + std::to_string(port) + "@evil.example/hooks",
          wht::hook_url(port, "/hooks/../admin"), std::string("not a url")}) {
        CAPTURE(url);
        const auto answer =
            post_json(client, "/v1/jobs", {{"analysis", "roll_gap"}, {"callback_url", url}});
        REQUIRE(answer);
        CHECK(answer->status == 422);
        const json problem = json::parse(answer->body);
        CHECK(problem["errors"][0]["pointer"] == "/callback_url");
    }
    const auto wrong_type =
        post_json(client, "/v1/jobs", {{"analysis", "roll_gap"}, {"callback_url", 42}});
    CHECK(wrong_type->status == 422);
    CHECK(body_json(client.Get("/v1/jobs"))["jobs"].empty());

    // a server that allows no callbacks says so
    TestServer plain;
    auto plain_client = plain.client();
    const auto refused =
        post_json(plain_client, "/v1/jobs",
                  {{"analysis", "roll_gap"}, {"callback_url", wht::hook_url(port)}});
    REQUIRE(refused);
    CHECK(refused->status == 422);
    CHECK(refused->body.find("--webhook-allow") != std::string::npos);
}
