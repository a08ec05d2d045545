#pragma once
// The checks a request passes before its body is read: route, method, bearer token, media
// type, declared length. They run in httplib's pre-routing hook and in its Expect:
// 100-continue hook, so a refused body is never read.

#include <httplib.h>

#include "service/config.h"
#include "service/http/routes.h"

namespace rollgap::service::http {

// Fills `response` and returns true if the request is refused before its body is read.
// `route` is match_route(request.path).
bool refuse(const Route* route, const httplib::Request& request, httplib::Response& response,
            const ServerConfig& config);

}  // namespace rollgap::service::http
