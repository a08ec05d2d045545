#include "service/http/static_files.h"

#include "embedded/app_js.h"
#include "embedded/api_js.h"
#include "embedded/chart_js.h"
#include "embedded/charts_js.h"
#include "embedded/editor_js.h"
#include "embedded/favicon_svg.h"
#include "embedded/heatmap_js.h"
#include "embedded/index_html.h"
#include "embedded/jobs_js.h"
#include "embedded/report_js.h"
#include "embedded/scenarios_js.h"
#include "embedded/state_js.h"
#include "embedded/style_css.h"
#include "embedded/views_js.h"

#include <array>
#include <cstdint>
#include <cstdio>
#include <string>

#include <httplib.h>

namespace rollgap::service {
namespace {

struct StaticFile {
    std::string_view path;
    std::string_view content_type;
    std::string_view (*body)();
};

constexpr std::string_view javascript = "text/javascript; charset=utf-8";

constexpr std::array files{
    StaticFile{"/", "text/html; charset=utf-8", web::index_html},
    StaticFile{"/static/style.css", "text/css; charset=utf-8", web::style_css},
    StaticFile{"/static/favicon.svg", "image/svg+xml", web::favicon_svg},
    StaticFile{"/static/chart.min.js", javascript, web::chart_js},
    StaticFile{"/static/js/app.js", javascript, web::app_js},
    StaticFile{"/static/js/api.js", javascript, web::api_js},
    StaticFile{"/static/js/charts.js", javascript, web::charts_js},
    StaticFile{"/static/js/editor.js", javascript, web::editor_js},
    StaticFile{"/static/js/heatmap.js", javascript, web::heatmap_js},
    StaticFile{"/static/js/jobs.js", javascript, web::jobs_js},
    StaticFile{"/static/js/report.js", javascript, web::report_js},
    StaticFile{"/static/js/scenarios.js", javascript, web::scenarios_js},
    StaticFile{"/static/js/state.js", javascript, web::state_js},
    StaticFile{"/static/js/views.js", javascript, web::views_js},
};

// A strong validator from the content (FNV-1a, 64 bit): it changes with the binary's files, so
// "no-cache" costs a browser one 304 per file instead of a download, and a new build is never
// mixed with cached old scripts.
std::string etag_of(std::string_view body) {
    std::uint64_t hash = 14695981039346656037ULL;
    for (const char c : body) {
        hash ^= static_cast<unsigned char>(c);
        hash *= 1099511628211ULL;
    }
    char text[24];
    std::snprintf(text, sizeof text, "\"%016llx\"", static_cast<unsigned long long>(hash));
    return text;
}

const std::array<std::string, files.size()>& etags() {
    static const auto computed = [] {
        std::array<std::string, files.size()> all;
        for (std::size_t i = 0; i < files.size(); ++i) all[i] = etag_of(files[i].body());
        return all;
    }();
    return computed;
}

}  // namespace

bool serve_static_file(const httplib::Request& request, httplib::Response& response) {
    for (std::size_t i = 0; i < files.size(); ++i) {
        if (files[i].path != request.path) continue;
        const std::string& etag = etags()[i];
        response.set_header("ETag", etag);
        response.set_header("Cache-Control", "no-cache");
        response.set_header("Content-Security-Policy", std::string(page_security_policy));
        response.set_header("X-Content-Type-Options", "nosniff");
        response.set_header("Referrer-Policy", "no-referrer");
        if (request.get_header_value("If-None-Match") == etag) {
            response.status = 304;
            return true;
        }
        response.status = 200;
        const std::string_view body = files[i].body();
        response.set_content(body.data(), body.size(), std::string(files[i].content_type));
        return true;
    }
    return false;
}

}  // namespace rollgap::service
