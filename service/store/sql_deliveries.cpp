// The job store's outbox of completion callbacks (docs/job-store.md, "Callbacks"): a delivery
// row is queued by the transaction that finishes its job (finish_job); any replica claims a
// due one under a lease, fixes its body at the first attempt and records each attempt's
// outcome. A replica that dies mid-attempt loses the lease and another attempts again: the
// receiver sees each delivery at least once, always under the same delivery id.

#include "service/store/sql_job_store.h"

#include <string>
#include <utility>

#include "service/store/job_rows.h"

namespace rollgap::service::store::detail {

Result<std::optional<Delivery>> SqlJobStore::claim_delivery(const std::string& owner,
                                                            std::chrono::milliseconds lease) {
    using Claimed = Result<std::optional<Delivery>>;
    const std::string due =
        "FROM webhook_deliveries WHERE state = 'pending' AND next_at_ms <= $1 "
        "AND (lease_until_ms IS NULL OR lease_until_ms < $1)";
    // A read first: the deliverer polls, and a write transaction would take SQLite's write lock
    // at every poll.
    bool any = false;
    auto looked = read(
        [&](Session& s) { any = !s.exec("SELECT 1 " + due + " LIMIT 1", {clock_()}).empty(); });
    if (looked.status != StoreStatus::ok) return Claimed::failure(looked.status, looked.detail);
    if (!any) return {StoreStatus::ok, std::optional<Delivery>{}, {}};

    std::optional<Delivery> claimed;
    const std::string token = random_hex();
    auto status = write(
        [&](Session& s) {
            const Millis now = clock_();
            const std::string skip_locked =
                backend_->dialect() == Dialect::postgresql ? " FOR UPDATE SKIP LOCKED" : "";
            const Rows rows = s.exec("SELECT id, job_id, url, job_state, body, attempts " + due +
                                         " ORDER BY next_at_ms, id LIMIT 1" + skip_locked,
                                     {now});
            if (rows.empty()) return;
            const Row& r = rows.at(0);
            Delivery d;
            d.id = r.at(0).value_or("");
            d.job_id = r.at(1).value_or("");
            d.url = r.at(2).value_or("");
            d.job_state = job_state_from_name(r.at(3).value_or("")).value_or(JobState::succeeded);
            d.body = r.at(4);
            d.attempts = to_int(r.at(5));
            d.token = token;
            s.exec(
                "UPDATE webhook_deliveries SET lease_token = $2, lease_owner = $3, "
                "lease_until_ms = $4 WHERE id = $1",
                {d.id, token, owner, now + lease.count()});
            claimed = std::move(d);
        },
        [&](Session& s) {
            return !s.exec("SELECT 1 FROM webhook_deliveries WHERE lease_token = $1", {token})
                        .empty();
        });
    if (status.status != StoreStatus::ok) return Claimed::failure(status.status, status.detail);
    return {StoreStatus::ok, std::move(claimed), {}};
}

StoreStatus SqlJobStore::set_delivery_body(const Delivery& delivery, const std::string& body) {
    return write(
               [&](Session& s) {
                   const Rows rows = s.exec(
                       "UPDATE webhook_deliveries SET body = COALESCE(body, $3) "
                       "WHERE id = $1 AND lease_token = $2 AND state = 'pending' RETURNING id",
                       {delivery.id, delivery.token, body});
                   if (rows.empty()) throw Abort{StoreStatus::conflict, "lease lost"};
               },
               {})
        .status;
}

StoreStatus SqlJobStore::record_delivery(const Delivery& delivery, DeliveryOutcome outcome,
                                         Millis next_at_ms, const std::string& error) {
    const std::string state = outcome == DeliveryOutcome::delivered ? "delivered"
                              : outcome == DeliveryOutcome::failed  ? "failed"
                                                                    : "pending";
    const Param last_error = error.empty() ? Param{nullptr} : Param{error};
    const Param finished = outcome == DeliveryOutcome::retry ? Param{nullptr} : Param{clock_()};
    return write(
               [&](Session& s) {
                   const Rows rows = s.exec(
                       "UPDATE webhook_deliveries SET state = $3, attempts = attempts + 1, "
                       "next_at_ms = $4, last_error = $5, finished_ms = $6, lease_token = NULL, "
                       "lease_owner = NULL, lease_until_ms = NULL "
                       "WHERE id = $1 AND lease_token = $2 AND state = 'pending' RETURNING id",
                       {delivery.id, delivery.token, state, next_at_ms, last_error, finished});
                   if (rows.empty()) throw Abort{StoreStatus::conflict, "lease lost"};
               },
               {})
        .status;
}

}  // namespace rollgap::service::store::detail
