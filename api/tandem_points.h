#pragma once
// What a mill sweep (api/tandem_sweep_json.h) and a mill map (api/tandem_map_json.h) share: a
// number of the tandem document named by a JSON pointer, its values written into the request's
// resolved mill and read back through the mill's own validation, and the document of one point
// (the mill's critical speeds, or its stability at its speed) (docs/model.md §12.10).

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/options_reader.h"
#include "api/sweep_json.h"
#include "api/units.h"
#include "core/control.h"
#include "core/mill/mill.h"
#include "core/stability.h"

namespace rollgap::api {

enum class TandemSweepQuantity { critical_speed, stability };

// What each point holds and how it is searched.
struct TandemPointSpec {
    TandemSweepQuantity quantity = TandemSweepQuantity::critical_speed;
    core::CriticalSpeedOptions critical_speed;
};

// Reads reader's "quantity" and "critical_speed" members into `spec`; `echo` gets both as
// applied (critical_speed only with quantity critical_speed, where it belongs).
void read_tandem_point_spec(const OptionsReader& reader, TandemPointSpec& spec,
                            nlohmann::json& echo);

// reader's "parameter": a JSON pointer naming a number or a list of numbers in `document` (the
// request's resolved mill; nullptr when the mill is invalid: only the shape is checked), with
// its unit; nothing with the violation recorded.
std::optional<std::string> read_tandem_parameter(const OptionsReader& reader,
                                                 const nlohmann::json* document, Unit& unit);

// Whether two parameters touch the same number (one is the other or lies inside it:
// "/spans/tension_MPa" and "/spans/tension_MPa/1").
bool tandem_parameters_overlap(const std::string& a, const std::string& b);

// `document` with `value` written at `parameter` (a list is set whole).
nlohmann::json with_tandem_value(nlohmann::json document, const std::string& parameter,
                                 double value);

// Each point written into `base` (a resolved tandem document) at `parameter` and read back as a
// request's tandem is: the valid points' values and mills, in order; a point the mill cannot have
// is a violation at the point's own pointer naming the field's bound and unit, or the mill rule
// the value breaks (a range reports its first bad interior point only).
struct TandemValues {
    std::vector<double> values;  // in the field's unit, as the client wrote them
    std::vector<core::Mill> mills;
};
TandemValues tandem_values(const std::vector<SweepPoint>& points, const nlohmann::json& base,
                           const std::string& parameter, FieldErrors& errors);

// One point's document: the point tables below, written for `mill`.
nlohmann::json tandem_point_json(const core::Mill& mill, const TandemPointSpec& spec,
                                 const core::Control& control);

// The point tables: OpenAPI component name, schema (members only) and scalar column names.
std::string_view tandem_point_component(TandemSweepQuantity quantity);
nlohmann::json tandem_point_schema(TandemSweepQuantity quantity);
std::vector<std::string> tandem_point_columns(TandemSweepQuantity quantity);
// A sheet's columns: `lead` (the swept values), then the columns of the points `result` holds
// (its "quantity").
std::vector<std::string> with_tandem_point_columns(std::vector<std::string> lead,
                                                   const nlohmann::json& result);

std::string_view to_string(TandemSweepQuantity quantity);

}  // namespace rollgap::api
