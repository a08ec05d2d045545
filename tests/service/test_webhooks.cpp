// Completion callbacks without HTTP (service/webhooks.h): which URLs the allow-list admits,
// compared on the parsed URL and never on its text; the signature against RFC 4231's published
// HMAC-SHA256 vectors; the retry schedule.

#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "service/webhooks.h"

using namespace rollgap::service;

namespace webhooks_test {

std::vector<WebhookUrl> prefixes(std::initializer_list<const char*> texts) {
    std::vector<WebhookUrl> out;
    for (const char* text : texts) {
        const auto parsed = parse_webhook_url(text);
        REQUIRE_MESSAGE(parsed, text);
        out.push_back(*parsed);
    }
    return out;
}

bool allowed(const char* url, const std::vector<WebhookUrl>& allow) {
    const auto parsed = parse_webhook_url(url);
    return parsed && webhook_allowed(*parsed, allow);
}

}  // namespace webhooks_test

namespace wt = webhooks_test;

TEST_CASE("webhook URLs: parsed into scheme, host, port, path and query") {
    const auto url = parse_webhook_url("HTTPS://MES.Plant.example/hooks/rollgap?line=3");
    REQUIRE(url);
    CHECK(url->scheme == "https");
    CHECK(url->host == "mes.plant.example");
    CHECK(url->port == 443);
    CHECK(url->path == "/hooks/rollgap");
    CHECK(url->query == "line=3");
    CHECK(url->target() == "/hooks/rollgap?line=3");
    CHECK(url->origin() == "https://mes.plant.example:443");
    const auto bare = parse_webhook_url("http://10.0.0.7:8088");
    REQUIRE(bare);
    CHECK(bare->port == 8088);
    CHECK(bare->path == "/");
    const auto v6 = parse_webhook_url("http://[::1]:9000/x");
    REQUIRE(v6);
    CHECK(v6->host == "[::1]");
    CHECK(v6->port == 9000);
    // refused rather than guessed: what another parser could read differently
    for (const char* bad :
         {"ftp://host/x", "http://user:pw@host/x", "http://host/x#frag", "http://host/a/../b",
          "http://host/a/./b", "http://host/a/%2E%2E/b", "http://host/a\\b", "http:/host/x",
          "http://host:0/x", "http://host:65536/x", "http://host:80x/x", "http://ho st/x",
          "http:///x", "http://host_name/x", "http://[::1/x", "host/x", ""}) {
        CAPTURE(bad);
        CHECK_FALSE(parse_webhook_url(bad));
    }
    CHECK_FALSE(parse_webhook_url("http://host/" + std::string(max_callback_url, 'a')));
}

TEST_CASE("webhook URLs: documents show them without their query") {
    CHECK(redacted_callback_url("https://mes.example:8443/hooks/rollgap?token=s3cret") ==
          "https://mes.example:8443/hooks/rollgap?…");
    CHECK(redacted_callback_url("http://10.0.0.5/hooks") == "http://10.0.0.5/hooks");
    CHECK(redacted_callback_url("not a url?token=s3cret") == "…");
}

TEST_CASE("webhook URLs: a prefix admits its scheme, host and port and its path's subtree") {
    const auto allow = wt::prefixes({"https://mes.plant.example/hooks", "http://10.0.0.7:8088/"});
    CHECK(wt::allowed("https://mes.plant.example/hooks", allow));
    CHECK(wt::allowed("https://mes.plant.example/hooks/rollgap?coil=C1", allow));
    CHECK(wt::allowed("https://MES.plant.example:443/hooks/x", allow));  // the default port
    CHECK(wt::allowed("http://10.0.0.7:8088/anything", allow));
    CHECK_FALSE(wt::allowed("https://mes.plant.example/hooks-evil", allow));  // not a segment
    CHECK_FALSE(wt::allowed("https://mes.plant.example/other", allow));
    CHECK_FALSE(wt::allowed("http://mes.plant.example/hooks", allow));            // scheme
    CHECK_FALSE(wt::allowed("https://mes.plant.example:8443/hooks", allow));      // port
    CHECK_FALSE(wt::allowed("https://mes.plant.example.evil.net/hooks", allow));  // host
    CHECK_FALSE(wt::allowed("https://mes.plant.example@evil.net/hooks", allow));  // userinfo
    CHECK_FALSE(wt::allowed("https://mes.plant.example/hooks/../admin", allow));  // dot segment
    CHECK_FALSE(wt::allowed("http://10.0.0.7/anything", allow));  // port 80, not 8088
    CHECK_FALSE(webhook_allowed(*parse_webhook_url("https://mes.plant.example/hooks"), {}));
}

TEST_CASE("webhook signature: HMAC-SHA256 as RFC 4231 publishes it, over timestamp.body") {
    // RFC 4231, test cases 1, 2 and 6 (a key longer than the block is hashed first).
    CHECK(hmac_sha256_hex(std::string(20, '\x0b'), "Hi There") ==
          "b0344c61d8db38535ca8afceaf0bf12b881dc200c9833da726e9376c2e32cff7");
    CHECK(hmac_sha256_hex("Jefe", "what do ya want for nothing?") ==
          "5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843");
    CHECK(hmac_sha256_hex(std::string(131, '\xaa'),
                          "Test Using Larger Than Block-Size Key - Hash Key First") ==
          "60e431591ee0b67f0d8a26aacbf5b77f8e0bc6213728c5140546040f0ee37f54");
    const std::string body = R"({"event":"job.finished"})";
    CHECK(webhook_signature("a-secret-of-16+chars", 1764900000, body) ==
          "v1=" + hmac_sha256_hex("a-secret-of-16+chars", "1764900000." + body));
    // the timestamp is signed: a replayed body under a new time does not verify
    CHECK(webhook_signature("a-secret-of-16+chars", 1764900001, body) !=
          webhook_signature("a-secret-of-16+chars", 1764900000, body));
}

TEST_CASE("webhook backoff: doubles from the base after each failed attempt, at most 5 min") {
    using std::chrono::milliseconds;
    CHECK(webhook_backoff(1, milliseconds(1000)) == milliseconds(1000));
    CHECK(webhook_backoff(2, milliseconds(1000)) == milliseconds(2000));
    CHECK(webhook_backoff(5, milliseconds(1000)) == milliseconds(16000));
    CHECK(webhook_backoff(9, milliseconds(1000)) == milliseconds(256000));
    CHECK(webhook_backoff(10, milliseconds(1000)) == max_webhook_backoff);
    CHECK(webhook_backoff(100, milliseconds(1000)) == max_webhook_backoff);
    CHECK(webhook_backoff(3, milliseconds(50)) == milliseconds(200));
}
