#include "service/http/service_state.h"

#include "service/http/responses.h"

namespace rollgap::service::http {

ServiceState::ServiceState(ServerConfig resolved, Evaluator evaluate)
    : config(std::move(resolved)), evaluator(evaluate ? std::move(evaluate) : facade_evaluator()),
      pool(config.workers, config.queue_length, 2 * config.max_jobs + 1, config.job_workers),
      store(config.store,
            store::StoreLimits{config.max_jobs, config.job_retention, config.store_connections,
                               config.store_deadline},
            config.instance) {}

void ServiceState::overloaded(httplib::Response& response, std::string detail) const {
    response.set_header("Retry-After", std::to_string(config.retry_after.count()));
    set_problem(response, api::ProblemCode::overloaded, std::move(detail));
}

void ServiceState::store_unavailable(httplib::Response& response, std::string detail) {
    store.report(store::StoreStatus::unavailable);
    response.set_header("Retry-After", std::to_string(config.retry_after.count()));
    set_problem(response, api::ProblemCode::store_unavailable, std::move(detail));
}

}  // namespace rollgap::service::http
