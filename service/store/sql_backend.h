#pragma once
// Internal to the job store: the small SQL surface both backends provide, so the store's
// rules (sql_job_store.cpp) are written once. Not part of the store's interface.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "service/store/job_store.h"

namespace rollgap::service::store::detail {

using Param = std::variant<std::nullptr_t, std::int64_t, double, std::string>;
using Value = std::optional<std::string>;
using Row = std::vector<Value>;
using Rows = std::vector<Row>;

enum class Dialect { sqlite, postgresql };

// Thrown by the store's rules inside a transaction to roll it back with a status; caught by
// Backend::transact, never leaves the store.
struct Abort {
    StoreStatus status;
    std::string detail;
};

class Session {
public:
    virtual ~Session() = default;
    // `sql` numbers its parameters $1, $2, … in both dialects.
    virtual Rows exec(std::string_view sql, const std::vector<Param>& params = {}) = 0;
};

class Backend {
public:
    virtual ~Backend() = default;
    virtual Dialect dialect() const = 0;
    // Runs `body` in one transaction; `write` marks a read-then-write transaction (SQLite
    // takes the write lock at BEGIN). If the commit's outcome is unknown, `verify` runs in a
    // new transaction and says whether the body's effect is there (then the result is ok);
    // without `verify` an unknown outcome is reported as unavailable.
    virtual StoreStatus transact(bool write, const std::function<void(Session&)>& body,
                                 const std::function<bool(Session&)>& verify,
                                 std::string& detail) = 0;
};

// Both open lazily enough to report `unavailable` through the returned status.
Result<std::unique_ptr<Backend>> open_sqlite(const std::string& path);
// `client_name`: the connections' application_name unless the DSN sets one.
Result<std::unique_ptr<Backend>> open_postgresql(const std::string& dsn,
                                                 const std::string& client_name);

std::shared_ptr<JobStore> make_sql_job_store(std::unique_ptr<Backend> backend, StoreLimits limits,
                                             Clock clock);
// Creates or migrates the schema; ok when it is at the newest version.
StoreStatus migrate(Backend& backend, std::string& detail);

// Text helpers shared by the backends.
std::string param_text(const Param& param);
std::int64_t to_int(const Value& value);

}  // namespace rollgap::service::store::detail
