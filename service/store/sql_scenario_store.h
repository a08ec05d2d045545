#pragma once
// Internal to the job store: stored scenarios over the SQL backends (table scenario_versions,
// migration 2). The job store's scenario operations delegate here.

#include "service/store/sql_backend.h"

namespace rollgap::service::store::detail {

bool valid_scenario_name(const std::string& name);

class SqlScenarioStore {
public:
    SqlScenarioStore(Backend& backend, const StoreLimits& limits, const Clock& clock)
        : backend_(backend), limits_(limits), clock_(clock) {}

    Result<StoredScenario> put(const std::string& name, const std::string& body,
                               std::optional<std::int64_t> if_match, const std::string& author,
                               StoredKind kind, const std::string& posterior);
    Result<StoredScenario> get(const std::string& name, std::optional<std::int64_t> version);
    StoreStatus remove(const std::string& name, std::optional<std::int64_t> if_match,
                       const std::string& author, StoredKind kind);
    Result<ScenarioPage> page(const ScenarioQuery& query);

private:
    Backend& backend_;
    const StoreLimits& limits_;
    const Clock& clock_;
};

}  // namespace rollgap::service::store::detail
