#pragma once
// The checks a request passes before its body is read: route, method, bearer token, media
// type, declared length. They run in httplib's pre-routing hook and in its Expect:
// 100-continue hook, so a refused body is never read.

#include <httplib.h>

#include "service/client_keys.h"
#include "service/config.h"
#include "service/http/routes.h"

namespace rollgap::service::http {

// Fills `response` and returns true if the request is refused before its body is read.
// `route` is match_route(request.path). On the public listener (`on_admin` false) the Host
// must be one of config.allowed_hosts (if any; else 421) and an unsafe method from a foreign
// browser origin is refused (403). When `keys` is enabled, a route that needs a key answers
// 401 without a known one and 403 without the scope (the route's scope: route_scope()).
// `client` is set to the key's name, or "anonymous" when no key is needed or configured.
bool refuse(const Route* route, const httplib::Request& request, httplib::Response& response,
            const ServerConfig& config, KeyRing& keys, bool on_admin, std::string& client);

// The largest body `route` reads: config.max_batch_body_bytes for POST /v1/batches (a batch of
// up to 10,000 items), config.max_body_bytes for every other route and an unmatched path.
std::size_t body_limit(const Route* route, const ServerConfig& config);

// The scope `method` on `route` needs (only for routes with `compute` set):
//   GET/HEAD of jobs and stored scenarios: read; PUT/DELETE of stored scenarios: write;
//   analyses, POST /v1/jobs and DELETE /v1/jobs/{id}: compute.
Scope route_scope(const Route& route, std::string_view method);

}  // namespace rollgap::service::http
