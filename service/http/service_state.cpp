#include "service/http/service_state.h"

#include "service/http/responses.h"

namespace rollgap::service::http {
namespace {

store::StoreLimits store_limits(const ServerConfig& config) {
    store::StoreLimits limits;
    limits.max_jobs = config.max_jobs;
    limits.max_finished_jobs = config.max_finished_jobs;
    limits.retention = config.job_retention;
    limits.max_retention = config.max_job_retention;
    limits.max_scenarios = config.max_scenarios;
    limits.connections = config.store_connections;
    limits.deadline = config.store_deadline;
    limits.client_name = "rollgap/" + config.instance;
    return limits;
}

}  // namespace

ServiceState::ServiceState(ServerConfig resolved, Evaluator evaluate)
    : config(std::move(resolved)), evaluator(evaluate ? std::move(evaluate) : facade_evaluator()),
      pool(config.workers, config.queue_length, 2 * config.max_jobs + 1, config.job_workers),
      store(config.store, store_limits(config), config.instance),
      keys(config.token, config.key_file) {}

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
