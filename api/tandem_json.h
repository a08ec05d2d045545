#pragma once
// The tandem document (api/tandem_schema.h): read strictly into core::Mill (SI), written back
// for echoing. A request's "tandem" is an RFC 7396 merge patch onto the default mill document
// (docs/model.md §12.3), as a request's "scenario" is onto the default scenario; arrays (the
// stands, the schedule, the spans) are replaced whole, as RFC 7396 says.

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/request_json.h"
#include "core/mill/mill.h"

namespace rollgap::api {

// core::default_mill() as a document, each stand an empty patch (the default scenario with the
// request's stand_defaults).
nlohmann::json default_tandem_json();

// A stand of the mill may be a stored stand scenario: "stands": [{}, {"base": "F2", ...}]. Only
// the service (it has the store) resolves the name, into the stand's complete scenario with the
// stand's own patch merged over it and "base": {"name", "version"}, the form read here and echoed
// (docs/http-api.md, "Stored stands in a mill"). One entry per stand, nullopt: not stored.
using StandBases = std::vector<std::optional<ScenarioBase>>;

// The complete document of a mill: the mill's fields, "stand_defaults": {} and each stand's
// complete scenario without the fields the mill gives it (with its base, when `bases` names
// one). Every mill result echoes it, so a result can be rerun.
nlohmann::json resolved_tandem_json(const core::Mill& mill, const StandBases* bases = nullptr);

// A stored stand's scenario document as a stand of a mill: without the fields the mill gives
// every stand (its thicknesses, tensions, width, …; its roll speed unless `speeds_mode`).
nlohmann::json without_mill_owned_fields(nlohmann::json stand, bool speeds_mode);

// Strict read. Violations are recorded under `pointer` ("/tandem"), each stand's at
// "/tandem/stands/<i>/...", a stand's value that the mill gives (its thickness, tension, ...)
// at the mill field that gives it. The returned mill is meaningful only if no error was
// recorded; it then passes core::mill_defect. A stand's "base" in its resolved form is read
// into `bases` (one entry per stand) when given; its name form is refused (it needs the store).
core::Mill mill_from_json(const nlohmann::json& document, const std::string& pointer,
                          FieldErrors& errors, StandBases* bases = nullptr);

// The merge patch onto default_tandem_json(), then read strictly.
core::Mill mill_from_patch(const nlohmann::json& patch, const std::string& pointer,
                           FieldErrors& errors, StandBases* bases = nullptr);

}  // namespace rollgap::api
