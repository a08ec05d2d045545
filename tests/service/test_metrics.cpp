// Prometheus metrics of the HTTP service (service/metrics.h): histogram buckets, the text
// format, label escaping, and — when promtool is installed — `promtool check metrics` on a
// live server's /metrics.

#include "service/metrics.h"

#include <doctest/doctest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "support/http_test.h"
#include "support/approx.h"

using namespace rollgap;
using namespace rollgap::service;

TEST_CASE(
    "metrics: a histogram counts each value in the first bucket whose bound is not below it") {
    static constexpr std::array<double, 3> bounds{0.1, 1.0, 10.0};
    Histogram histogram(bounds);
    histogram.observe(0.1);                                       // le 0.1
    histogram.observe(0.5);                                       // le 1
    histogram.observe(20.0);                                      // +Inf
    histogram.observe(std::numeric_limits<double>::quiet_NaN());  // ignored
    CHECK(histogram.count() == 3);
    CHECK(histogram.sum() == rollgap::test::approx(20.6));
    CHECK(histogram.bucket_counts() == std::vector<std::uint64_t>{1, 1, 0, 1});
}

TEST_CASE(
    "metrics: the exposition has HELP and TYPE, cumulative buckets, and counts per label set") {
    Metrics metrics;
    metrics.observe_request("POST", "/v1/roll-gap", 200, 0.002);
    metrics.observe_request("POST", "/v1/roll-gap", 200, 0.004);
    metrics.observe_request("POST", "/v1/roll-gap", 503, 0.0001);
    metrics.observe_analysis("roll_gap", "succeeded", 0.001);
    metrics.count_solver_failure("roll_gap", "internal");
    const std::vector<GaugeSample> gauges{
        {"rollgap_queue_depth", "Waiting work.", "lane=\"interactive\"", 3}};
    const std::string text = metrics.render(gauges);

    CHECK(text.find("# TYPE rollgap_http_requests_total counter\n") != std::string::npos);
    CHECK(
        text.find(
            "rollgap_http_requests_total{method=\"POST\",route=\"/v1/roll-gap\",status=\"200\"} 2\n") !=
        std::string::npos);
    CHECK(
        text.find(
            "rollgap_http_requests_total{method=\"POST\",route=\"/v1/roll-gap\",status=\"503\"} 1\n") !=
        std::string::npos);
    CHECK(text.find("# TYPE rollgap_http_request_duration_seconds histogram\n") !=
          std::string::npos);
    CHECK(text.find(
              "rollgap_http_request_duration_seconds_bucket{method=\"POST\",route=\"/v1/roll-gap\","
              "status=\"200\",le=\"0.0025\"} 1\n") != std::string::npos);
    CHECK(text.find(
              "rollgap_http_request_duration_seconds_bucket{method=\"POST\",route=\"/v1/roll-gap\","
              "status=\"200\",le=\"0.005\"} 2\n") != std::string::npos);
    CHECK(text.find(
              "rollgap_http_request_duration_seconds_bucket{method=\"POST\",route=\"/v1/roll-gap\","
              "status=\"200\",le=\"+Inf\"} 2\n") != std::string::npos);
    CHECK(text.find(
              "rollgap_http_request_duration_seconds_count{method=\"POST\",route=\"/v1/roll-gap\","
              "status=\"200\"} 2\n") != std::string::npos);
    CHECK(
        text.find("rollgap_solver_failures_total{analysis=\"roll_gap\",reason=\"internal\"} 1\n") !=
        std::string::npos);
    CHECK(text.find(
              "# TYPE rollgap_queue_depth gauge\nrollgap_queue_depth{lane=\"interactive\"} 3\n") !=
          std::string::npos);
    CHECK(text.find("rollgap_build_info{version=") != std::string::npos);
    CHECK(metrics.request_count("POST", "/v1/roll-gap", 200) == 2);
}

TEST_CASE("metrics: label values are escaped") {
    CHECK(escape_label_value("a\"b\\c\nd") == "a\\\"b\\\\c\\nd");
}

TEST_CASE("metrics: a live server's /metrics passes promtool check metrics") {
    test::TestServer server;
    auto client = server.client();
    REQUIRE(client.Get("/livez"));
    REQUIRE(test::post_json(client, "/v1/roll-gap", {{"options", {{"distributions", false}}}}));
    REQUIRE(client.Get("/nothing-here"));
    // A request is counted after its answer is written: wait until the 404 shows.
    std::string text;
    CHECK(test::eventually([&] {
        const auto metrics = client.Get("/metrics");
        if (!metrics || metrics->status != 200) return false;
        CHECK(metrics->get_header_value("Content-Type").starts_with("text/plain; version=0.0.4"));
        text = metrics->body;
        return text.find("route=\"unmatched\",status=\"404\"") != std::string::npos;
    }));
    for (const char* name :
         {"rollgap_http_requests_total", "rollgap_http_request_duration_seconds_bucket",
          "rollgap_analysis_duration_seconds_bucket", "rollgap_queue_depth", "rollgap_workers_busy",
          "rollgap_workers", "rollgap_jobs", "rollgap_build_info",
          "process_resident_memory_bytes"}) {
        CAPTURE(name);
        CHECK(text.find(name) != std::string::npos);
    }

    const char* promtool = "/usr/bin/promtool";
    if (!std::filesystem::exists(promtool)) {
        MESSAGE(
            "promtool not installed (apt-get install prometheus; scripts/check-http.sh does): "
            "skipping `promtool check metrics`");
        return;
    }
    const auto path = std::filesystem::temp_directory_path() /
                      ("rollgap-metrics-" + std::to_string(::getpid()) + ".txt");
    std::ofstream(path) << text;
    const std::string command =
        std::string(promtool) + " check metrics < " + path.string() + " 2>&1";
    FILE* pipe = ::popen(command.c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::string output;
    char buffer[512];
    while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
    const int status = ::pclose(pipe);
    std::filesystem::remove(path);
    CAPTURE(output);
    CHECK(status == 0);
    CHECK(output.empty());  // no lint findings either
}
