// SQLite backend: one connection per store, guarded by a mutex.
//
// Why not one connection per thread: SQLite lets one writer in at a time whatever the number
// of connections, and every transaction here is a few short statements, so per-thread
// connections would only add lock hand-offs between them (and connections of finished
// threads to clean up). The mutex serializes this process's transactions; `BEGIN IMMEDIATE`
// plus the busy timeout serialize them with other processes on the same file (a replaced
// replica still running during a restart), because a deferred transaction that reads and
// then writes fails with SQLITE_BUSY instead of waiting.

#include <filesystem>
#include <mutex>
#include <string>

#include <sqlite3.h>

#include "service/store/sql_backend.h"
#include "service/store/store_executor.h"

namespace rollgap::service::store::detail {
namespace {

struct SqliteError {
    int code;
    std::string message;
};

StoreStatus status_of(int code) {
    switch (code & 0xff) {
        case SQLITE_CONSTRAINT: return StoreStatus::conflict;
        default: return StoreStatus::unavailable;  // busy, locked, I/O, full disk, read-only, …
    }
}

// `$1` → `?1`: SQLite reads `$1` as a named parameter, numbered by first appearance.
std::string sqlite_sql(std::string_view sql) {
    std::string text(sql);
    for (char& c : text) {
        if (c == '$') c = '?';
    }
    return text;
}

class SqliteSession final : public Session {
public:
    explicit SqliteSession(sqlite3* db) : db_(db) {}

    Rows exec(std::string_view sql, const std::vector<Param>& params) override {
        const std::string text = sqlite_sql(sql);
        sqlite3_stmt* raw = nullptr;
        check(sqlite3_prepare_v2(db_, text.c_str(), static_cast<int>(text.size()), &raw, nullptr));
        std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)> statement(raw, sqlite3_finalize);
        for (std::size_t i = 0; i < params.size(); ++i) {
            const int at = static_cast<int>(i + 1);
            const Param& p = params[i];
            if (std::holds_alternative<std::nullptr_t>(p)) check(sqlite3_bind_null(raw, at));
            else if (const auto* n = std::get_if<std::int64_t>(&p))
                check(sqlite3_bind_int64(raw, at, *n));
            else if (const auto* d = std::get_if<double>(&p))
                check(sqlite3_bind_double(raw, at, *d));
            else {
                const auto& s = std::get<std::string>(p);
                check(sqlite3_bind_text(raw, at, s.data(), static_cast<int>(s.size()),
                                        SQLITE_TRANSIENT));
            }
        }
        Rows rows;
        for (;;) {
            const int step = sqlite3_step(raw);
            if (step == SQLITE_DONE) break;
            if (step != SQLITE_ROW) check(step);
            Row row;
            const int columns = sqlite3_column_count(raw);
            for (int c = 0; c < columns; ++c) {
                if (sqlite3_column_type(raw, c) == SQLITE_NULL) {
                    row.emplace_back(std::nullopt);
                } else {
                    const auto* bytes = reinterpret_cast<const char*>(sqlite3_column_text(raw, c));
                    row.emplace_back(
                        std::string(bytes, static_cast<std::size_t>(sqlite3_column_bytes(raw, c))));
                }
            }
            rows.push_back(std::move(row));
        }
        return rows;
    }

    void check(int code) const {
        if (code != SQLITE_OK && code != SQLITE_ROW && code != SQLITE_DONE) {
            throw SqliteError{code, sqlite3_errmsg(db_)};
        }
    }

private:
    sqlite3* db_;
};

class SqliteBackend final : public Backend {
public:
    explicit SqliteBackend(sqlite3* db) : db_(db) {}
    ~SqliteBackend() override { sqlite3_close_v2(db_); }
    SqliteBackend(const SqliteBackend&) = delete;
    SqliteBackend& operator=(const SqliteBackend&) = delete;

    Dialect dialect() const override { return Dialect::sqlite; }

    StoreStatus transact(bool write, const std::function<void(Session&)>& body,
                         const std::function<bool(Session&)>&, std::string& detail) override {
        // A failed COMMIT in SQLite leaves the transaction not committed (no unknown outcome),
        // so `verify` is never needed here.
        std::lock_guard guard(mutex_);
        // A file deleted (or replaced) under the service: the connection would go on writing
        // to the unlinked inode, and every job accepted would vanish at the next start.
        int moved = 0;
        if (sqlite3_file_control(db_, "main", SQLITE_FCNTL_HAS_MOVED, &moved) == SQLITE_OK &&
            moved != 0) {
            detail = moved_detail;
            return StoreStatus::unavailable;
        }
        SqliteSession session(db_);
        try {
            session.exec(write ? "BEGIN IMMEDIATE" : "BEGIN", {});
        } catch (const SqliteError& e) {
            detail = e.message;
            return StoreStatus::unavailable;
        }
        try {
            body(session);
            session.exec("COMMIT", {});
            return StoreStatus::ok;
        } catch (const Abort& a) {
            detail = a.detail;
            rollback();
            return a.status;
        } catch (const SqliteError& e) {
            detail = e.message;
            rollback();
            return status_of(e.code);
        } catch (const std::exception& e) {
            detail = e.what();
            rollback();
            return StoreStatus::unavailable;
        }
    }

private:
    void rollback() {
        if (!sqlite3_get_autocommit(db_)) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    }

    std::mutex mutex_;
    sqlite3* db_;
};

}  // namespace

Result<std::unique_ptr<Backend>> open_sqlite(const std::string& path) {
    using R = Result<std::unique_ptr<Backend>>;
    // The data directory of a fresh installation: created (owner only), so the first start
    // needs no step of its own.
    if (const auto parent = std::filesystem::path(path).parent_path(); !parent.empty()) {
        std::error_code error;
        // Only a directory made here gets its permissions set: an existing one is the
        // operator's.
        if (std::filesystem::create_directories(parent, error) && !error) {
            std::filesystem::permissions(parent, std::filesystem::perms::owner_all,
                                         std::filesystem::perm_options::replace, error);
        }
    }
    sqlite3* db = nullptr;
    const int opened =
        sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr);
    if (opened != SQLITE_OK) {
        std::string why = db != nullptr ? sqlite3_errmsg(db) : "cannot open";
        sqlite3_close_v2(db);
        return R::failure(StoreStatus::unavailable, why);
    }
    auto backend = std::make_unique<SqliteBackend>(db);
    // WAL: readers do not block the writer; synchronous FULL: a committed job survives a power
    // loss, since a client was told it exists.
    constexpr const char* setup =
        "PRAGMA busy_timeout = 5000; PRAGMA journal_mode = WAL; PRAGMA synchronous = FULL; PRAGMA foreign_keys = ON;";
    char* error = nullptr;
    if (sqlite3_exec(db, setup, nullptr, nullptr, &error) != SQLITE_OK) {
        std::string why = error != nullptr ? error : "setup";
        sqlite3_free(error);
        return R::failure(StoreStatus::unavailable, why);
    }
    return {StoreStatus::ok, std::unique_ptr<Backend>(std::move(backend)), {}};
}

}  // namespace rollgap::service::store::detail
