#pragma once
// JSON Merge Patch (RFC 7396): a request's scenario is a patch onto the default scenario, so a
// client sends only what differs, and `null` removes a member (here: back to its default).

#include <nlohmann/json.hpp>

namespace rollgap::api {

// RFC 7396 §2 MergePatch(target, patch). Recursive in the depth of `patch`: callers bound the
// depth of client JSON first (json_text.h).
nlohmann::json merge_patch(nlohmann::json target, const nlohmann::json& patch);

}  // namespace rollgap::api
