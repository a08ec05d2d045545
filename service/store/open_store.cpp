// The `--store` setting → a migrated store.

#include <algorithm>
#include <fstream>
#include <sstream>

#include "service/store/dsn_redaction.h"
#include "service/store/sql_backend.h"
#include "service/store/store_executor.h"

namespace rollgap::service::store {
namespace {

bool starts_with(const std::string& text, std::string_view prefix) {
    return text.rfind(prefix, 0) == 0;
}

std::string trimmed(std::string text) {
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos) return {};
    const auto last = text.find_last_not_of(" \t\r\n");
    return text.substr(first, last - first + 1);
}

}  // namespace

Result<std::shared_ptr<JobStore>> open_store(const std::string& setting, StoreLimits limits,
                                             Clock clock) {
    using R = Result<std::shared_ptr<JobStore>>;
    Result<std::unique_ptr<detail::Backend>> backend;
    std::string dsn;  // a PostgreSQL DSN: its secrets are taken out of every detail below
    if (starts_with(setting, "sqlite:")) {
        const std::string path = setting.substr(7);
        if (path.empty()) return R::failure(StoreStatus::invalid, "sqlite: needs a file path");
        backend = detail::open_sqlite(path);
    } else if (starts_with(setting, "postgresql://") || starts_with(setting, "postgres://")) {
        dsn = setting;
        backend = detail::open_postgresql(dsn, limits.client_name);
    } else if (starts_with(setting, "postgresql-file:")) {
        // The DSN's file (a mounted Secret); its text never goes into a detail or a log.
        std::ifstream file(setting.substr(16));
        if (!file) return R::failure(StoreStatus::invalid, "the DSN file cannot be read");
        std::stringstream text;
        text << file.rdbuf();
        dsn = trimmed(text.str());
        if (!starts_with(dsn, "postgresql://") && !starts_with(dsn, "postgres://")) {
            return R::failure(StoreStatus::invalid,
                              "the DSN file does not hold a postgresql:// DSN");
        }
        backend = detail::open_postgresql(dsn, limits.client_name);
    } else {
        return R::failure(StoreStatus::invalid,
                          "expected sqlite:PATH, postgresql://… or postgresql-file:PATH");
    }
    if (!backend.ok()) return R::failure(backend.status, redact_dsn_secrets(backend.detail, dsn));
    // Every operation, the migration included, runs on the executor's threads: they hold the
    // store's only connections. The migration may wait for another replica's: a longer
    // deadline.
    auto executor = std::make_unique<detail::StoreExecutor>(
        std::move(*backend.value),
        detail::ExecutorOptions{
            limits.connections,
            std::max<std::chrono::milliseconds>(limits.deadline, std::chrono::seconds(30))});
    std::string detail;
    if (const auto migrated = detail::migrate(*executor, detail); migrated != StoreStatus::ok) {
        return R::failure(StoreStatus::unavailable, redact_dsn_secrets(detail, dsn));
    }
    executor->set_deadline(limits.deadline);
    return {StoreStatus::ok,
            detail::make_sql_job_store(std::move(executor), limits, std::move(clock)),
            {}};
}

}  // namespace rollgap::service::store
