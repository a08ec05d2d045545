#pragma once
// Analysis "batch" (docs/http-api.md, "Batches"): many requests of one non-pointwise analysis
// (typically speed_limit, one per coil) run as one job whose points are the items, so a job
// spreads them over the workers of every replica (service/chunked.h). Each item is computed
// exactly as its own request would be (evaluate()), and its row carries its key figures or
// its own problem: an item that fails never fails the batch.
//
// Options:
//   analysis   the items' analysis: a stand's or a mill's, not pointwise, not batch
//   scenario | tandem   a merge patch every item's subject starts from (the analysis' subject)
//   base       a stored stand or mill every item without its own starts from (the service
//              resolves it; the CLI has no store)
//   options    the options every item starts from; an item's own options are merged onto them.
//              speed_limit's what_to_change is false unless asked (a batch wants headlines)
//   items      1..10,000 of {label, scenario | tandem, base, options}: label 1..128 characters

#include "service/analyses/analysis.h"

namespace rollgap::service {

PreparedAnalysis prepare_batch(nlohmann::json options, const std::string& options_pointer,
                               api::FieldErrors& errors);

// Item `index`'s request as the batch runs it: {"analysis", "scenario"|"tandem", "options",
// "base"?}. `options` is a batch's options as prepare_batch accepted them.
nlohmann::json batch_item_request(const nlohmann::json& options, std::size_t index);

}  // namespace rollgap::service
