#pragma once
// The browser workbench (web/): its files are compiled into the binary (cmake/Embed.cmake), so
// `rollgap serve` alone serves the page at / and its scripts and styles under /static/, with
// nothing to deploy next to it and nothing fetched from elsewhere at run time.

#include <string_view>

namespace httplib {
struct Request;
struct Response;
}  // namespace httplib

namespace rollgap::service {

// What the page may load: only this origin, no inline script or style, no framing. Every
// script and style of the page is a separate file, so this holds.
inline constexpr std::string_view page_security_policy =
    "default-src 'self'; base-uri 'none'; form-action 'self'; frame-ancestors 'none'; object-src 'none'";

// Answers a GET or HEAD of a workbench file: 200 with its content type, ETag and the security
// headers, or 304 when If-None-Match names the current ETag. False, untouched, when there is
// no such file.
bool serve_static_file(const httplib::Request& request, httplib::Response& response);

}  // namespace rollgap::service
