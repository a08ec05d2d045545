// The store's schema, created and migrated by the store itself. Each version is applied once,
// in one transaction, and recorded in schema_migrations; replicas starting together serialize
// on a lock (PostgreSQL advisory lock, SQLite's write lock), so exactly one applies it.

#include <array>
#include <string>
#include <string_view>

#include "service/store/sql_backend.h"

namespace rollgap::service::store::detail {
namespace {

// `{SEQ}` is the insertion-order key: newest-first listing and the cursor use it.
constexpr std::array<std::string_view, 6> version_1 = {
    R"(CREATE TABLE jobs (
        {SEQ},
        id TEXT NOT NULL UNIQUE,
        analysis TEXT NOT NULL,
        request TEXT NOT NULL,
        state TEXT NOT NULL,
        progress DOUBLE PRECISION NOT NULL DEFAULT 0,
        result TEXT,
        problem TEXT,
        instance TEXT NOT NULL,
        worker TEXT,
        created_ms BIGINT NOT NULL,
        started_ms BIGINT,
        finished_ms BIGINT,
        deadline_ms BIGINT NOT NULL,
        cancel_requested INTEGER NOT NULL DEFAULT 0,
        idempotency_key TEXT UNIQUE,
        body_hash TEXT NOT NULL,
        points BIGINT NOT NULL,
        chunk_size BIGINT NOT NULL,
        chunks BIGINT NOT NULL))",
    "CREATE INDEX jobs_state_seq ON jobs (state, seq)",
    "CREATE INDEX jobs_finished ON jobs (finished_ms)",
    R"(CREATE TABLE chunks (
        job_id TEXT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
        idx BIGINT NOT NULL,
        job_seq BIGINT NOT NULL,
        begin_point BIGINT NOT NULL,
        end_point BIGINT NOT NULL,
        state TEXT NOT NULL,
        lease_token TEXT,
        lease_owner TEXT,
        lease_until_ms BIGINT,
        result TEXT,
        PRIMARY KEY (job_id, idx)))",
    "CREATE INDEX chunks_claim ON chunks (state, job_seq, idx)",
    R"(CREATE TABLE scenarios (
        name TEXT PRIMARY KEY,
        body TEXT NOT NULL,
        version BIGINT NOT NULL,
        updated_ms BIGINT NOT NULL))",
};

// Stored scenarios become versions (issue 16): one row per write, the counter of a name kept
// across deletes (a delete is a row marked `deleted`), the history per name bounded by the
// store. `kind` tells stand scenarios from later kinds (stored mills).
constexpr std::array<std::string_view, 4> version_2 = {
    R"(CREATE TABLE scenario_versions (
        name TEXT NOT NULL,
        version BIGINT NOT NULL,
        kind TEXT NOT NULL DEFAULT 'stand',
        body TEXT NOT NULL,
        author TEXT NOT NULL,
        created BIGINT NOT NULL,
        deleted INTEGER NOT NULL DEFAULT 0,
        PRIMARY KEY (name, version)))",
    // Versions written before authors were recorded.
    "INSERT INTO scenario_versions (name, version, kind, body, author, created, deleted) "
    "SELECT name, version, 'stand', body, 'unknown', updated_ms, 0 FROM scenarios",
    "DROP TABLE scenarios",
    // Counting and listing the live names reads this index only, never the bodies.
    "CREATE INDEX scenario_versions_live ON scenario_versions (deleted, name, version)",
};

// A stored stand keeps its calibration posterior (issue 20): the fitted fields with their
// standard errors and correlation as JSON, NULL for a version without one.
constexpr std::array<std::string_view, 1> version_3 = {
    "ALTER TABLE scenario_versions ADD COLUMN posterior TEXT",
};

// Jobs for an MES (issue 21): the client's labels (also a table of their own, indexed for the
// list's filter) and a retention chosen per job.
constexpr std::array<std::string_view, 4> version_4 = {
    "ALTER TABLE jobs ADD COLUMN labels TEXT",
    "ALTER TABLE jobs ADD COLUMN retention_ms BIGINT",
    R"(CREATE TABLE job_labels (
        job_id TEXT NOT NULL,
        name TEXT NOT NULL,
        value TEXT NOT NULL,
        PRIMARY KEY (job_id, name)))",
    "CREATE INDEX job_labels_value ON job_labels (name, value)",
};

// Completion callbacks (issue 21): the job's callback URL, and the outbox of deliveries, one row
// per finished job that asked for one, inserted in the transaction that finishes the job and
// claimed by any replica under a lease (docs/job-store.md, "Callbacks").
constexpr std::array<std::string_view, 3> version_5 = {
    "ALTER TABLE jobs ADD COLUMN callback_url TEXT",
    R"(CREATE TABLE webhook_deliveries (
        id TEXT PRIMARY KEY,
        job_id TEXT NOT NULL UNIQUE,
        url TEXT NOT NULL,
        job_state TEXT NOT NULL,
        body TEXT,
        state TEXT NOT NULL,
        attempts BIGINT NOT NULL DEFAULT 0,
        next_at_ms BIGINT NOT NULL,
        lease_token TEXT,
        lease_owner TEXT,
        lease_until_ms BIGINT,
        last_error TEXT,
        created_ms BIGINT NOT NULL,
        finished_ms BIGINT))",
    "CREATE INDEX webhook_deliveries_due ON webhook_deliveries (state, next_at_ms)",
};

std::string dialect_sql(std::string_view sql, Dialect dialect) {
    std::string text(sql);
    const std::string_view key = "{SEQ}";
    if (const auto at = text.find(key); at != std::string::npos) {
        text.replace(at, key.size(),
                     dialect == Dialect::sqlite ? "seq INTEGER PRIMARY KEY AUTOINCREMENT"
                                                : "seq BIGSERIAL PRIMARY KEY");
    }
    return text;
}

}  // namespace

StoreStatus migrate(Backend& backend, std::string& detail) {
    const Dialect dialect = backend.dialect();
    return backend.transact(
        true,
        [&](Session& s) {
            if (dialect == Dialect::postgresql) {
                // Any constant: the key of "the schema is being migrated".
                s.exec("SELECT pg_advisory_xact_lock(7216541)");
            }
            s.exec(
                "CREATE TABLE IF NOT EXISTS schema_migrations (version BIGINT PRIMARY KEY, applied_ms BIGINT NOT NULL)");
            // The health probe's write (JobStore::probe); outside the versions: no data.
            s.exec(
                "CREATE TABLE IF NOT EXISTS store_heartbeat (instance TEXT PRIMARY KEY, at_ms BIGINT NOT NULL)");
            const Rows rows = s.exec("SELECT COALESCE(MAX(version), 0) FROM schema_migrations");
            const std::int64_t current = to_int(rows.at(0).at(0));
            if (current < 1) {
                for (std::string_view statement : version_1)
                    s.exec(dialect_sql(statement, dialect));
                s.exec("INSERT INTO schema_migrations (version, applied_ms) VALUES ($1, $2)",
                       {std::int64_t{1}, system_millis()});
            }
            if (current < 2) {
                for (std::string_view statement : version_2) s.exec(statement);
                s.exec("INSERT INTO schema_migrations (version, applied_ms) VALUES ($1, $2)",
                       {std::int64_t{2}, system_millis()});
            }
            if (current < 3) {
                for (std::string_view statement : version_3) s.exec(statement);
                s.exec("INSERT INTO schema_migrations (version, applied_ms) VALUES ($1, $2)",
                       {std::int64_t{3}, system_millis()});
            }
            if (current < 4) {
                for (std::string_view statement : version_4) s.exec(statement);
                s.exec("INSERT INTO schema_migrations (version, applied_ms) VALUES ($1, $2)",
                       {std::int64_t{4}, system_millis()});
            }
            if (current < 5) {
                for (std::string_view statement : version_5) s.exec(statement);
                s.exec("INSERT INTO schema_migrations (version, applied_ms) VALUES ($1, $2)",
                       {std::int64_t{5}, system_millis()});
            }
        },
        {}, detail);
}

}  // namespace rollgap::service::store::detail
