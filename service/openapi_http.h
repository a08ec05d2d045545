#pragma once
// What the HTTP layer gives every operation of the OpenAPI document, whatever its route: the
// answers the connection sends before (or instead of) a handler, the request id on every
// request and answer, the poll hint of a 202, and whether a request body may be left out.

#include <nlohmann/json.hpp>

namespace rollgap::service {

// Completes `document` (its operations and component responses as written): adds the
// transport statuses (400, 406, 408, 414, 421, 431) to every operation, the X-Request-Id
// parameter and response header everywhere, Retry-After on every 202, and marks a request
// body optional where its schema accepts {} (an empty body is the request {}).
void add_http_conventions(nlohmann::json& document);

// Request bodies without `default`s: a generated client (openapi-typescript with its default
// options) makes a member with a default required, so a merge patch or a partial options
// object could not be typed. Every component a request body reaches whose members carry
// defaults is given to requests without them: in place when no answer uses it, else as a copy
// named <component>Input (the answers' echoes keep the defaults, which are the service's).
// The defaults stay in the descriptions' text and in the answers' components.
void split_request_components(nlohmann::json& document);

}  // namespace rollgap::service
