// The browser workbench as the service serves it: the page and every file it references come
// from the binary, under a Content-Security-Policy that forbids inline script and style, with
// validators for caching. (What the page does in a browser: tests/browser/.)

#include <doctest/doctest.h>

#include <fstream>
#include <iterator>
#include <set>
#include <string>

#include "support/http_test.h"

using namespace rollgap::test;

namespace {

// Every `attribute="value"` in `text` whose value starts with `prefix`.
std::set<std::string> references(const std::string& text, const std::string& attribute,
                                 const std::string& prefix) {
    std::set<std::string> found;
    const std::string opening = attribute + "=\"" + prefix;
    for (std::size_t at = text.find(opening); at != std::string::npos;
         at = text.find(opening, at + 1)) {
        const std::size_t start = at + attribute.size() + 2;
        found.insert(text.substr(start, text.find('"', start) - start));
    }
    return found;
}

}  // namespace

TEST_CASE("workbench: GET / is the page under a CSP without inline script or style") {
    TestServer server;
    auto client = server.client();
    const auto page = client.Get("/");
    REQUIRE(page);
    CHECK(page->status == 200);
    CHECK(page->get_header_value("Content-Type") == "text/html; charset=utf-8");
    const std::string csp = page->get_header_value("Content-Security-Policy");
    CHECK(csp.find("default-src 'self'") != std::string::npos);
    CHECK(csp.find("unsafe-inline") == std::string::npos);
    CHECK(csp.find("unsafe-eval") == std::string::npos);
    CHECK(page->get_header_value("X-Content-Type-Options") == "nosniff");
    // The policy can hold only if the page itself has no inline code or style.
    CHECK(page->body.find("<style") == std::string::npos);
    CHECK(page->body.find(" style=") == std::string::npos);
    // No event-handler attributes either:
    for (const char* handler : {" onclick=", " onload=", " onerror=", " onchange=", " oninput="}) {
        CHECK(page->body.find(handler) == std::string::npos);
    }
    for (std::size_t at = page->body.find("<script"); at != std::string::npos;
         at = page->body.find("<script", at + 1)) {
        const std::string tag = page->body.substr(at, page->body.find('>', at) - at);
        CAPTURE(tag);
        CHECK(tag.find(" src=\"/static/") != std::string::npos);
    }
    const auto head = client.Head("/");
    REQUIRE(head);
    CHECK(head->status == 200);
    CHECK(head->body.empty());
}

TEST_CASE("workbench: every file the page and its modules reference is served with its type") {
    TestServer server;
    auto client = server.client();
    const auto page = client.Get("/");
    REQUIRE(page);
    std::set<std::string> files = references(page->body, "src", "/static/");
    files.merge(references(page->body, "href", "/static/"));
    REQUIRE(files.count("/static/js/app.js") == 1);
    REQUIRE(files.count("/static/chart.min.js") == 1);
    // The modules import each other as './<name>.js': follow them from app.js.
    std::set<std::string> pending = {"/static/js/app.js"};
    while (!pending.empty()) {
        const std::string module = *pending.begin();
        pending.erase(pending.begin());
        const auto script = client.Get(module);
        REQUIRE(script);
        CAPTURE(module);
        REQUIRE(script->status == 200);
        const std::string& text = script->body;
        for (std::size_t at = text.find("from './"); at != std::string::npos;
             at = text.find("from './", at + 1)) {
            const std::size_t start = at + 8;
            const std::string path =
                "/static/js/" + text.substr(start, text.find('\'', start) - start);
            if (files.insert(path).second) pending.insert(path);
        }
    }
    CHECK(files.size() >= 10);
    for (const std::string& file : files) {
        CAPTURE(file);
        const auto result = client.Get(file);
        REQUIRE(result);
        CHECK(result->status == 200);
        CHECK(!result->body.empty());
        const std::string type = result->get_header_value("Content-Type");
        if (file.ends_with(".js")) CHECK(type == "text/javascript; charset=utf-8");
        if (file.ends_with(".css")) CHECK(type == "text/css; charset=utf-8");
        if (file.ends_with(".svg")) CHECK(type == "image/svg+xml");
        CHECK(!result->get_header_value("Content-Security-Policy").empty());
    }
}

TEST_CASE("workbench: Chart.js is Debian's file, byte for byte") {
    std::ifstream debian("/usr/share/javascript/chart.js/chart.min.js", std::ios::binary);
    REQUIRE_MESSAGE(debian, "libjs-chart.js is not installed");
    const std::string expected((std::istreambuf_iterator<char>(debian)),
                               std::istreambuf_iterator<char>());
    TestServer server;
    auto client = server.client();
    const auto served = client.Get("/static/chart.min.js");
    REQUIRE(served);
    CHECK(served->status == 200);
    CHECK(served->body.size() == expected.size());
    CHECK(served->body == expected);
}

TEST_CASE("workbench: an ETag revalidates to 304, an unknown file is a 404 problem") {
    TestServer server;
    auto client = server.client();
    const auto first = client.Get("/static/js/app.js");
    REQUIRE(first);
    const std::string etag = first->get_header_value("ETag");
    REQUIRE(etag.size() > 2);
    CHECK(first->get_header_value("Cache-Control") == "no-cache");
    const auto again = client.Get("/static/js/app.js", {{"If-None-Match", etag}});
    REQUIRE(again);
    CHECK(again->status == 304);
    CHECK(again->body.empty());
    const auto stale = client.Get("/static/js/app.js", {{"If-None-Match", "\"0000\""}});
    REQUIRE(stale);
    CHECK(stale->status == 200);
    CHECK(stale->body == first->body);
    CHECK(client.Get("/")->get_header_value("ETag") != etag);

    const auto missing = client.Get("/static/nothing.js");
    REQUIRE(missing);
    CHECK(missing->status == 404);
    CHECK(missing->get_header_value("Content-Type") == "application/problem+json");
    const auto post = client.Post("/", "{}", "application/json");
    REQUIRE(post);
    CHECK(post->status == 405);
}
