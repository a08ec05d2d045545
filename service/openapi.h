#pragma once
// The OpenAPI 3.1 document served at GET /openapi.json: service/openapi.json (embedded at build
// time) completed at run time from the tables the service really uses, so the document cannot
// drift from the code:
//   - components.schemas.Scenario and ScenarioPatch from the api scenario field table (unit,
//     bounds and default of every field, unknown fields forbidden),
//   - the problem codes from api's problem table, the analysis names from the facade's table,
//   - info.version from the build.

#include <string>

#include <nlohmann/json.hpp>

namespace rollgap::service {

// JSON Schema (2020-12, as OpenAPI 3.1 uses it) of the complete scenario document.
// `patch`: the schema of a request's merge patch instead (every member optional and nullable).
nlohmann::json scenario_json_schema(bool patch);
// The tandem document (api/tandem_schema.h) as a JSON Schema: complete (echoed in a mill's
// results) or as a merge patch (a request's "tandem").
nlohmann::json tandem_json_schema(bool patch);

nlohmann::json openapi_document();
const std::string& openapi_text();  // openapi_document().dump(), computed once

}  // namespace rollgap::service
