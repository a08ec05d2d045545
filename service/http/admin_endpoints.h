#pragma once
// The health and metrics endpoints: /livez, /readyz, /metrics. Served on the public listener
// and on the admin listener, whose threads public connections cannot take.

#include <string>

#include <httplib.h>

#include "service/http/routes.h"
#include "service/http/service_state.h"

namespace rollgap::service::http {

// Answers `route` (livez, readyz or metrics).
void answer_admin(RouteId route, ServiceState& state, httplib::Response& response);

// The Prometheus text exposition of the service.
std::string metrics_text(ServiceState& state);

}  // namespace rollgap::service::http
