#pragma once
// Strict reading of an analysis's options object, member by member: the object itself, its
// unknown members, then each member with its type, bounds and unit. A missing member keeps the
// default already in the target; a violation is recorded (and the default stays, so reading
// goes on and every violation is reported at once).

#include <span>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/interval.h"
#include "api/option_table.h"
#include "api/units.h"

namespace rollgap::api {

class OptionsReader {
public:
    // Records "must be an object" or the unknown members of `options` under `pointer`.
    OptionsReader(const nlohmann::json& options, std::string pointer,
                  std::span<const std::string_view> known, FieldErrors& errors);

    bool is_object() const { return object_ != nullptr; }
    const std::string& pointer() const { return pointer_; }
    std::string at(std::string_view name) const;  // the pointer of a member
    FieldErrors& errors() const { return errors_; }

    // The member, or nullptr if absent (or if the options are not an object).
    const nlohmann::json* find(std::string_view name) const;
    // A nested options object documented "absent or null: the defaults": the member, or an
    // empty object when it is absent or null (an echo writes null for one that does not apply).
    const nlohmann::json& object_or_defaults(std::string_view name) const;
    // Whether the member is present and not null.
    bool given(std::string_view name) const {
        const nlohmann::json* member = find(name);
        return member != nullptr && !member->is_null();
    }

    // Each returns true if the member was present and valid (and stored), false otherwise.
    // Numbers are stored in SI: `unit` is the unit of the member as the client writes it.
    bool number(std::string_view name, Unit unit, const Interval& range, double& si_target) const;
    bool integer(std::string_view name, const Interval& range, int& target) const;
    bool boolean(std::string_view name, bool& target) const;

    // A scalar option by its row (api/option_table.h): name, type, unit and bounds from the
    // row. The target's type must be the row's (double: number, int: integer, bool: boolean).
    bool read(OptionId id, double& si_target) const;
    bool read(OptionId id, int& target) const;
    bool read(OptionId id, bool& target) const;

    // Whether a violation was recorded at or below a member.
    bool failed(std::string_view name) const { return errors_.has_error_at_or_below(at(name)); }
    bool failed(OptionId id) const { return failed(option(id).name); }

private:
    const nlohmann::json* object_ = nullptr;
    std::string pointer_;
    FieldErrors& errors_;
};

// A number in the client's unit, ready to echo: the SI value converted back (exact for values
// the client sent, units.h).
inline double echo(double value_si, Unit unit) { return from_si(value_si, unit); }

// An option's echo written into `document` under its row's name: a number in the client's unit
// (echo above), an integer or a boolean.
void put_option(nlohmann::json& document, OptionId id, double value_si);
void put_option(nlohmann::json& document, OptionId id, int value);
void put_option(nlohmann::json& document, OptionId id, bool value);

}  // namespace rollgap::api
