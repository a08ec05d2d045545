// PostgreSQL backend: one connection per thread (a libpqxx connection is not thread-safe, and
// a pool of worker threads each holding its own keeps transactions independent), opened on
// first use with a connect timeout and dropped on any connection failure so that the next
// transaction reconnects (libpqxx would otherwise reconnect silently and lose session state).

#include <atomic>
#include <map>
#include <string>

#include <pqxx/pqxx>

#include "service/store/sql_backend.h"

namespace rollgap::service::store::detail {
namespace {

// Connections of this thread, by backend serial (a serial, not an address, so a new backend
// at a reused address never picks up an old backend's connection). A thread's connections
// close when it exits.
thread_local std::map<std::uint64_t, std::unique_ptr<pqxx::connection>> thread_connections;
std::atomic<std::uint64_t> next_serial{1};

constexpr int max_attempts = 4;  // deadlock or serialization failure: run the transaction again

std::string with_connect_timeout(const std::string& dsn) {
    if (dsn.find("connect_timeout") != std::string::npos) return dsn;
    const bool uri = dsn.rfind("postgresql://", 0) == 0 || dsn.rfind("postgres://", 0) == 0;
    if (!uri) return dsn + " connect_timeout=5";
    return dsn + (dsn.find('?') == std::string::npos ? "?" : "&") + "connect_timeout=5";
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
    explicit PostgresBackend(std::string dsn) : dsn_(with_connect_timeout(dsn)) {}
    ~PostgresBackend() override { thread_connections.erase(serial_); }
    PostgresBackend(const PostgresBackend&) = delete;
    PostgresBackend& operator=(const PostgresBackend&) = delete;

    Dialect dialect() const override { return Dialect::postgresql; }

    StoreStatus transact(bool, const std::function<void(Session&)>& body,
                         const std::function<bool(Session&)>& verify,
                         std::string& detail) override {
        for (int attempt = 1;; ++attempt) {
            try {
                pqxx::work tx(connection());
                PostgresSession session(tx);
                body(session);
                try {
                    tx.commit();
                } catch (const pqxx::in_doubt_error& e) {
                    // The commit was sent but its answer lost: it may or may not have happened.
                    detail = e.what();
                    drop();
                    return verify ? settle(verify, detail) : StoreStatus::unavailable;
                }
                return StoreStatus::ok;
            } catch (const Abort& a) {
                detail = a.detail;
                return a.status;
            } catch (const pqxx::broken_connection& e) {
                detail = e.what();
                drop();
                return StoreStatus::unavailable;
            } catch (const pqxx::transaction_rollback& e) {
                // Deadlock or serialization failure: nothing was written; try again.
                detail = e.what();
                if (attempt >= max_attempts) return StoreStatus::unavailable;
            } catch (const pqxx::unique_violation& e) {
                detail = e.what();
                return StoreStatus::conflict;
            } catch (const std::exception& e) {
                detail = e.what();
                if (!connection_open()) drop();
                return StoreStatus::unavailable;
            }
        }
    }

private:
    pqxx::connection& connection() {
        auto& slot = thread_connections[serial_];
        if (!slot || !slot->is_open()) slot = std::make_unique<pqxx::connection>(dsn_);
        return *slot;
    }
    bool connection_open() const {
        const auto it = thread_connections.find(serial_);
        return it != thread_connections.end() && it->second && it->second->is_open();
    }
    void drop() { thread_connections.erase(serial_); }

    // After an unknown commit outcome: look, on a new connection, whether the effect is there.
    StoreStatus settle(const std::function<bool(Session&)>& verify, std::string& detail) {
        try {
            pqxx::read_transaction tx(connection());
            PostgresSession session(tx);
            return verify(session) ? StoreStatus::ok : StoreStatus::unavailable;
        } catch (const std::exception& e) {
            detail = e.what();
            drop();
            return StoreStatus::unavailable;
        }
    }

    std::string dsn_;
    std::uint64_t serial_ = next_serial.fetch_add(1);
};

}  // namespace

Result<std::unique_ptr<Backend>> open_postgresql(const std::string& dsn) {
    return {StoreStatus::ok, std::unique_ptr<Backend>(std::make_unique<PostgresBackend>(dsn)), {}};
}

}  // namespace rollgap::service::store::detail
