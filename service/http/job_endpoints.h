#pragma once
// The job endpoints: POST /v1/jobs (the facade's envelope check, then the batch lane),
// GET and DELETE /v1/jobs/{id}. A job's scenario and options are checked when it runs.

#include <memory>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "service/http/service_state.h"

namespace rollgap::service::http {

class JobEndpoints {
public:
    explicit JobEndpoints(ServiceState& state) : state_(state) {}

    void create(nlohmann::json request, httplib::Response& response);
    void get(const std::string& id, httplib::Response& response);
    // A queued job leaves the batch lane at once, so its slot is free again.
    void cancel(const std::string& id, httplib::Response& response);

private:
    void run(const std::shared_ptr<Job>& job);
    void not_found(const std::string& id, httplib::Response& response);

    ServiceState& state_;
};

}  // namespace rollgap::service::http
