// Stored scenarios over the SQL backends: every write is a new row of scenario_versions, so a
// name's version counts up for ever (a delete is a version too, marked `deleted`), and an
// editor's stale If-Match can never match a scenario created again under the same name. The
// history per name is bounded (StoreLimits::scenario_history); a deleted name keeps only its
// marker, which holds the counter. The markers are bounded too (StoreLimits::deleted_names):
// the oldest go, and the highest version they held becomes the floor, kept in the row of the
// name '' (never a valid name), above which every name that has no row starts, so a name that
// lost its marker still never sees a version again.

#include "service/store/sql_scenario_store.h"

#include "api/request_json.h"

#include <algorithm>

namespace rollgap::service::store::detail {
namespace {

constexpr std::string_view kind_stand = "stand";

std::string kind_text(StoredKind kind) { return std::string(stored_kind_name(kind)); }

// The newest version of a name: version, deleted, body, created, author, kind, posterior; none
// if never stored.
std::optional<Row> newest(Session& s, const std::string& name, std::string_view lock) {
    const Rows rows = s.exec(
        "SELECT version, deleted, body, created, author, kind, posterior FROM scenario_versions "
        "WHERE name = $1 "
        "ORDER BY version DESC LIMIT 1" +
            std::string(lock),
        {name});
    if (rows.empty()) return std::nullopt;
    return rows.front();
}

// Live scenarios: names whose newest version is not a delete (index scenario_versions_live).
constexpr std::string_view live =
    "v.deleted = 0 AND NOT EXISTS (SELECT 1 FROM scenario_versions w "
    "WHERE w.name = v.name AND w.version > v.version)";

// The version below which no name without rows may start (0 until a marker was dropped).
std::int64_t version_floor(Session& s) {
    const Rows rows =
        s.exec("SELECT COALESCE(MAX(version), 0) FROM scenario_versions WHERE name = ''");
    return rows.empty() ? 0 : to_int(rows.front().at(0));
}

// Keeps at most `bound` deleted names' markers: the oldest others go, their versions raise the
// floor.
void bound_deleted_names(Session& s, std::size_t bound, std::int64_t now) {
    const std::string markers =
        "FROM scenario_versions v WHERE v.deleted = 1 AND v.name <> '' AND NOT EXISTS "
        "(SELECT 1 FROM scenario_versions w WHERE w.name = v.name AND w.version > v.version)";
    const std::int64_t count = to_int(s.exec("SELECT COUNT(*) " + markers).at(0).at(0));
    const auto keep = static_cast<std::int64_t>(bound);
    if (count <= keep) return;
    std::int64_t floor = version_floor(s);
    const Rows oldest =
        s.exec("SELECT v.name, v.version " + markers + " ORDER BY v.created, v.name LIMIT $1",
               {count - keep});
    for (const Row& row : oldest) {
        floor = std::max(floor, to_int(row.at(1)));
        s.exec("DELETE FROM scenario_versions WHERE name = $1", {row.at(0).value_or("")});
    }
    s.exec("DELETE FROM scenario_versions WHERE name = ''");
    s.exec(
        "INSERT INTO scenario_versions (name, version, kind, body, author, created, deleted) "
        "VALUES ('', $1, $2, '', '', $3, 1)",
        {floor, std::string(kind_stand), now});
}

std::optional<StoreStatus> refuse_name(const std::string& name) {
    if (name == api::reserved_scenario_name || !valid_scenario_name(name))
        return StoreStatus::invalid;
    return std::nullopt;
}

StoreStatus run(Backend& backend, bool write, const std::function<void(Session&)>& body,
                std::string& detail) {
    return backend.transact(write, body, {}, detail);
}

}  // namespace

// The API's rule for stored scenario names (api/request_json.h), kept here too: a name that
// reaches the store any other way is refused as well.
bool valid_scenario_name(const std::string& name) { return api::is_stored_scenario_name(name); }

Result<StoredScenario> SqlScenarioStore::put(const std::string& name, const std::string& body,
                                             std::optional<std::int64_t> if_match,
                                             const std::string& author, StoredKind kind,
                                             const std::string& posterior) {
    if (auto refused = refuse_name(name)) return Result<StoredScenario>::failure(*refused, "name");
    const bool postgresql = backend_.dialect() == Dialect::postgresql;
    StoredScenario stored{name, body, 0, 0, author, false, kind, posterior};
    std::string detail;
    const StoreStatus status = run(
        backend_, true,
        [&](Session& s) {
            stored.updated_ms = clock_();
            const auto current = newest(s, name, postgresql ? " FOR UPDATE" : "");
            const bool exists = current && to_int(current->at(1)) == 0;
            if (!exists) {
                if (if_match) throw Abort{StoreStatus::conflict, "no such version"};
                // Creators of different names serialize here, so the bound holds exactly
                // (SQLite's BEGIN IMMEDIATE already serializes every write).
                if (postgresql) s.exec("SELECT pg_advisory_xact_lock(7216542)");
                const std::string count_sql =
                    "SELECT COUNT(*) FROM scenario_versions v WHERE " + std::string(live);
                if (to_int(s.exec(count_sql).at(0).at(0)) >=
                    static_cast<std::int64_t>(limits_.max_scenarios)) {
                    throw Abort{StoreStatus::full, "max_scenarios"};
                }
            } else if (current->at(5).value_or(kind_stand.data()) != stored_kind_name(kind)) {
                // A name is one thing at a time: a mill does not replace a stand.
                throw Abort{StoreStatus::conflict, std::string(kind_conflict_detail)};
            } else if (!if_match || *if_match != to_int(current->at(0))) {
                // Replacing a stored scenario needs the version the editor started from, so
                // that two editors cannot overwrite each other.
                throw Abort{StoreStatus::conflict, "version mismatch"};
            }
            stored.created = !exists;
            stored.version = current ? to_int(current->at(0)) + 1 : version_floor(s) + 1;
            // A creator racing on a name never stored before: the key (name, version) lets one
            // win; the other sees a conflict, as an editor with a stale version does.
            const Param posterior_value = posterior.empty() ? Param(nullptr) : Param(posterior);
            if (s.exec("INSERT INTO scenario_versions (name, version, kind, body, author, created, "
                       "deleted, posterior) VALUES ($1, $2, $3, $4, $5, $6, 0, $7) "
                       "ON CONFLICT (name, version) DO NOTHING RETURNING version",
                       {name, stored.version, kind_text(kind), body, author, stored.updated_ms,
                        posterior_value})
                    .empty()) {
                throw Abort{StoreStatus::conflict, "created meanwhile"};
            }
            const auto keep =
                static_cast<std::int64_t>(std::max<std::size_t>(limits_.scenario_history, 1));
            s.exec("DELETE FROM scenario_versions WHERE name = $1 AND version <= $2",
                   {name, stored.version - keep});
        },
        detail);
    if (status != StoreStatus::ok) return Result<StoredScenario>::failure(status, detail);
    return {StoreStatus::ok, std::move(stored), {}};
}

Result<StoredScenario> SqlScenarioStore::get(const std::string& name,
                                             std::optional<std::int64_t> version) {
    if (auto refused = refuse_name(name)) return Result<StoredScenario>::failure(*refused, "name");
    StoredScenario found;
    std::string detail;
    const StoreStatus status = run(
        backend_, false,
        [&](Session& s) {
            std::optional<Row> current;
            if (version) {
                const Rows rows = s.exec(
                    "SELECT version, deleted, body, created, author, kind, posterior FROM "
                    "scenario_versions WHERE name = $1 AND version = $2",
                    {name, *version});
                if (!rows.empty()) current = rows.front();
            } else {
                current = newest(s, name, "");
            }
            if (!current || to_int(current->at(1)) != 0) throw Abort{StoreStatus::not_found, {}};
            found = {
                name,
                current->at(2).value_or(""),
                to_int(current->at(0)),
                to_int(current->at(3)),
                current->at(4).value_or(""),
                false,
                current->at(5).value_or(kind_stand.data()) == stored_kind_name(StoredKind::mill)
                    ? StoredKind::mill
                    : StoredKind::stand,
                current->at(6).value_or("")};
        },
        detail);
    if (status != StoreStatus::ok) return Result<StoredScenario>::failure(status, detail);
    return {StoreStatus::ok, std::move(found), {}};
}

StoreStatus SqlScenarioStore::remove(const std::string& name, std::optional<std::int64_t> if_match,
                                     const std::string& author, StoredKind kind) {
    if (auto refused = refuse_name(name)) return *refused;
    const bool postgresql = backend_.dialect() == Dialect::postgresql;
    std::string detail;
    return run(
        backend_, true,
        [&](Session& s) {
            const auto current = newest(s, name, postgresql ? " FOR UPDATE" : "");
            if (!current || to_int(current->at(1)) != 0 ||
                current->at(5).value_or(kind_stand.data()) != stored_kind_name(kind)) {
                throw Abort{StoreStatus::not_found, {}};
            }
            const std::int64_t version = to_int(current->at(0));
            if (if_match && *if_match != version)
                throw Abort{StoreStatus::conflict, "version mismatch"};
            // The marker keeps the counter (and who deleted it); the older bodies go, so names
            // created and deleted keep one small row each.
            s.exec(
                "INSERT INTO scenario_versions (name, version, kind, body, author, created, "
                "deleted) VALUES ($1, $2, $3, '', $4, $5, 1)",
                {name, version + 1, kind_text(kind), author, clock_()});
            s.exec("DELETE FROM scenario_versions WHERE name = $1 AND version <= $2",
                   {name, version});
            bound_deleted_names(s, std::max<std::size_t>(limits_.deleted_names, 1), clock_());
        },
        detail);
}

Result<ScenarioPage> SqlScenarioStore::page(const ScenarioQuery& query) {
    if (query.cursor && !valid_scenario_name(*query.cursor))
        return Result<ScenarioPage>::failure(StoreStatus::invalid, "cursor");
    const std::size_t limit = std::max<std::size_t>(query.limit, 1);
    ScenarioPage page;
    std::string detail;
    const StoreStatus status = run(
        backend_, false,
        [&](Session& s) {
            const Rows rows = s.exec(
                "SELECT v.name, v.version, v.created, v.author FROM scenario_versions v WHERE " +
                    std::string(live) + " AND v.kind = $1 AND v.name > $2 ORDER BY v.name LIMIT $3",
                {kind_text(query.kind), query.cursor.value_or(""),
                 static_cast<std::int64_t>(limit + 1)});
            for (std::size_t i = 0; i < rows.size() && i < limit; ++i) {
                const Row& r = rows[i];
                page.scenarios.push_back({r.at(0).value_or(""),
                                          {},
                                          to_int(r.at(1)),
                                          to_int(r.at(2)),
                                          r.at(3).value_or(""),
                                          false,
                                          query.kind,
                                          {}});
            }
            if (rows.size() > limit) page.next_cursor = page.scenarios.back().name;
        },
        detail);
    if (status != StoreStatus::ok) return Result<ScenarioPage>::failure(status, detail);
    return {StoreStatus::ok, std::move(page), {}};
}

}  // namespace rollgap::service::store::detail
