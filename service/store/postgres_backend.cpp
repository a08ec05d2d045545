// PostgreSQL backend: a small pool of connections (a libpqxx connection is not thread-safe,
// so a transaction has one to itself). Only the store executor's N threads call transact
// (store_executor.h), so the pool never holds more than N: that, not the HTTP threads, bounds a
// replica's connections. A connection idle for a while is closed; one found broken when its
// transaction begins (the server restarted, a partition cut it) is replaced and the
// transaction run again on a fresh one, so the first operation after a restart succeeds.

#include <cctype>
#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <pqxx/pqxx>

#include "service/store/dsn_redaction.h"
#include "service/store/sql_backend.h"

namespace rollgap::service::store::detail {
namespace {

using SteadyClock = std::chrono::steady_clock;

constexpr int max_attempts = 4;  // deadlock or serialization failure: run the transaction again
// A connection unused this long is closed (the background probe keeps one in use).
constexpr std::chrono::seconds idle_timeout{30};

// libpq options the DSN does not set itself: a bounded connect, and TCP keepalives plus a user
// timeout so that a call stuck on a silent network returns an error (and frees its executor
// thread) instead of waiting for ever; and the replica's name as application_name.
std::string with_connection_options(const std::string& dsn, const std::string& client_name) {
    const bool uri = dsn.rfind("postgresql://", 0) == 0 || dsn.rfind("postgres://", 0) == 0;
    // application_name: at most 63 bytes are kept by the server; printable ASCII only.
    std::string name;
    for (const char c : client_name.substr(0, 63)) name += (c > ' ' && c < 0x7f) ? c : '_';
    std::string text = dsn;
    for (const auto& [option, value] :
         std::map<std::string, std::string>{{"connect_timeout", "5"},
                                            {"keepalives", "1"},
                                            {"keepalives_idle", "5"},
                                            {"keepalives_interval", "2"},
                                            {"keepalives_count", "3"},
                                            {"tcp_user_timeout", "10000"},
                                            {"application_name", name}}) {
        if (value.empty() || dsn.find(option + "=") != std::string::npos) continue;
        if (uri) {
            // A URI's query value: percent-encoded but for the unreserved characters.
            std::string encoded;
            for (const char c : value) {
                const bool unreserved = std::isalnum(static_cast<unsigned char>(c)) != 0 ||
                                        c == '-' || c == '.' || c == '_' || c == '~';
                if (unreserved) {
                    encoded += c;
                } else {
                    char hex[4];
                    std::snprintf(hex, sizeof hex, "%%%02X", static_cast<unsigned char>(c));
                    encoded += hex;
                }
            }
            text += (text.find('?') == std::string::npos ? "?" : "&") + option + "=" + encoded;
        } else {
            // A keyword/value string: quoted, with ' and \ escaped.
            std::string quoted = "'";
            for (const char c : value) {
                if (c == '\'' || c == '\\') quoted += '\\';
                quoted += c;
            }
            text += " " + option + "=" + quoted + "'";
        }
    }
    return text;
}

class PostgresSession final : public Session {
public:
    explicit PostgresSession(pqxx::transaction_base& tx) : tx_(tx) {}

    Rows exec(std::string_view sql, const std::vector<Param>& params) override {
        std::vector<std::string> texts;
        texts.reserve(params.size());
        std::vector<const char*> values;  // nullptr is SQL NULL
        values.reserve(params.size());
        for (const Param& p : params) texts.push_back(param_text(p));
        for (std::size_t i = 0; i < params.size(); ++i) {
            values.push_back(std::holds_alternative<std::nullptr_t>(params[i]) ? nullptr
                                                                               : texts[i].c_str());
        }
        const pqxx::result result =
            tx_.exec_params(std::string(sql), pqxx::prepare::make_dynamic_params(values));
        Rows rows;
        rows.reserve(result.size());
        for (const auto& r : result) {
            Row row;
            row.reserve(r.size());
            for (const auto& field : r) {
                row.emplace_back(field.is_null() ? Value{}
                                                 : Value{std::string(field.c_str(), field.size())});
            }
            rows.push_back(std::move(row));
        }
        return rows;
    }

private:
    pqxx::transaction_base& tx_;
};

class PostgresBackend final : public Backend {
public:
    PostgresBackend(const std::string& dsn, const std::string& client_name)
        : dsn_(with_connection_options(dsn, client_name)) {}

    Dialect dialect() const override { return Dialect::postgresql; }

    StoreStatus transact(bool, const std::function<void(Session&)>& body,
                         const std::function<bool(Session&)>& verify,
                         std::string& detail) override {
        bool replaced = false;  // a broken pooled connection was replaced once already
        for (int attempt = 1;; ++attempt) {
            std::unique_ptr<pqxx::connection> connection;
            bool fresh = false;
            bool began = false;  // the body ran (its effects on the caller may not be repeated)
            try {
                connection = acquire(fresh);
                bool in_doubt = false;
                {
                    // The transaction ends (and rolls back if not committed) before its
                    // connection goes back to the pool.
                    pqxx::work tx(*connection);
                    PostgresSession session(tx);
                    began = true;
                    body(session);
                    try {
                        tx.commit();
                    } catch (const pqxx::in_doubt_error& e) {
                        // The commit was sent but its answer lost: it may or may not have
                        // happened.
                        detail = redact_dsn_secrets(e.what(), dsn_);
                        in_doubt = true;
                    }
                }
                if (in_doubt) {
                    connection.reset();
                    return verify ? settle(verify, detail) : StoreStatus::unavailable;
                }
                release(std::move(connection));
                return StoreStatus::ok;
            } catch (const Abort& a) {
                detail = a.detail;
                release(std::move(connection));
                return a.status;
            } catch (const pqxx::transaction_rollback& e) {
                // Deadlock or serialization failure: nothing was written; try again.
                detail = redact_dsn_secrets(e.what(), dsn_);
                release(std::move(connection));
                if (attempt >= max_attempts) return StoreStatus::unavailable;
            } catch (const pqxx::unique_violation& e) {
                detail = redact_dsn_secrets(e.what(), dsn_);
                release(std::move(connection));
                return StoreStatus::conflict;
            } catch (const std::exception& e) {
                detail = redact_dsn_secrets(e.what(), dsn_);
                const bool broken = connection && !connection->is_open();
                const bool stale = !began && !fresh && connection != nullptr;
                if (broken || stale || dynamic_cast<const pqxx::broken_connection*>(&e) != nullptr)
                    connection.reset();
                else release(std::move(connection));
                // A pooled connection that failed before the body ran (the server restarted
                // since it was last used): nothing was sent that counts; run it again once on a
                // new connection.
                if (stale && !replaced) {
                    replaced = true;
                    discard_idle();  // opened before the same restart, most likely
                    continue;
                }
                return StoreStatus::unavailable;
            }
        }
    }

private:
    // A pooled connection (the most recently used: the others age out) or a new one.
    std::unique_ptr<pqxx::connection> acquire(bool& fresh) {
        std::vector<std::unique_ptr<pqxx::connection>> expired;  // closed outside the lock
        std::unique_ptr<pqxx::connection> connection;
        {
            std::lock_guard lock(mutex_);
            close_idle(expired);
            while (!idle_.empty() && !connection) {
                connection = std::move(idle_.back().connection);
                idle_.pop_back();
                if (!connection->is_open()) expired.push_back(std::move(connection));
            }
        }
        if (connection) return connection;
        fresh = true;
        return std::make_unique<pqxx::connection>(dsn_);
    }

    void discard_idle() {
        std::vector<Idle> discarded;
        {
            std::lock_guard lock(mutex_);
            discarded.swap(idle_);
        }
    }

    void release(std::unique_ptr<pqxx::connection> connection) {
        if (!connection || !connection->is_open()) return;
        std::vector<std::unique_ptr<pqxx::connection>> expired;
        std::lock_guard lock(mutex_);
        idle_.push_back({std::move(connection), SteadyClock::now()});
        close_idle(expired);
    }

    void close_idle(std::vector<std::unique_ptr<pqxx::connection>>& expired) {
        const auto now = SteadyClock::now();
        for (auto it = idle_.begin(); it != idle_.end();) {
            if (now - it->since > idle_timeout) {
                expired.push_back(std::move(it->connection));
                it = idle_.erase(it);
            } else {
                ++it;
            }
        }
    }

    // After an unknown commit outcome: look, on a new connection, whether the effect is there.
    StoreStatus settle(const std::function<bool(Session&)>& verify, std::string& detail) {
        try {
            bool fresh = false;
            auto connection = acquire(fresh);
            bool found = false;
            {
                pqxx::read_transaction tx(*connection);
                PostgresSession session(tx);
                found = verify(session);
            }
            release(std::move(connection));
            return found ? StoreStatus::ok : StoreStatus::unavailable;
        } catch (const std::exception& e) {
            detail = redact_dsn_secrets(e.what(), dsn_);
            return StoreStatus::unavailable;
        }
    }

    struct Idle {
        std::unique_ptr<pqxx::connection> connection;
        SteadyClock::time_point since;
    };

    std::string dsn_;
    std::mutex mutex_;
    std::vector<Idle> idle_;
};

}  // namespace

Result<std::unique_ptr<Backend>> open_postgresql(const std::string& dsn,
                                                 const std::string& client_name) {
    return {StoreStatus::ok,
            std::unique_ptr<Backend>(std::make_unique<PostgresBackend>(dsn, client_name)),
            {}};
}

}  // namespace rollgap::service::store::detail
