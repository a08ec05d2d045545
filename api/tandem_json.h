#pragma once
// The tandem document (api/tandem_schema.h): read strictly into core::Mill (SI), written back
// for echoing. A request's "tandem" is an RFC 7396 merge patch onto the default mill document
// (docs/model.md §12.3), as a request's "scenario" is onto the default scenario; arrays (the
// stands, the schedule, the spans) are replaced whole, as RFC 7396 says.

#include <string>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "core/mill/mill.h"

namespace rollgap::api {

// core::default_mill() as a document, each stand an empty patch (the default scenario with the
// request's stand_defaults).
nlohmann::json default_tandem_json();

// The complete document of a mill: the mill's fields, "stand_defaults": {} and each stand's
// complete scenario without the fields the mill gives it. Every mill result echoes it, so a
// result can be rerun.
nlohmann::json resolved_tandem_json(const core::Mill& mill);

// Strict read. Violations are recorded under `pointer` ("/tandem"), each stand's at
// "/tandem/stands/<i>/...", a stand's value that the mill gives (its thickness, tension, ...)
// at the mill field that gives it. The returned mill is meaningful only if no error was
// recorded; it then passes core::mill_defect.
core::Mill mill_from_json(const nlohmann::json& document, const std::string& pointer,
                          FieldErrors& errors);

// The merge patch onto default_tandem_json(), then read strictly.
core::Mill mill_from_patch(const nlohmann::json& patch, const std::string& pointer,
                           FieldErrors& errors);

}  // namespace rollgap::api
