#pragma once
// Strict reading of client JSON: every violation is collected (not only the first) as a
// FieldError with its JSON pointer, so a client fixes a request in one round trip.

#include <functional>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/interval.h"
#include "api/problem.h"
#include "api/units.h"

namespace rollgap::api {

class FieldErrors {
public:
    // Beyond `reporting_cap` errors only a count is kept: a request with 10^5 unknown fields
    // must not produce a 10^5-item response.
    static constexpr std::size_t default_reporting_cap = 100;
    explicit FieldErrors(std::size_t reporting_cap = default_reporting_cap);

    void add(FieldError error);
    bool empty() const { return count_ == 0; }
    bool reporting_full() const { return reported_.size() >= reporting_cap_; }
    std::size_t size() const { return count_; }
    const std::vector<FieldError>& reported() const { return reported_; }

    // Whether a violation was recorded at `pointer` or below it: cross-field checks skip
    // fields that are already known to be wrong.
    bool has_error_at_or_below(std::string_view pointer) const;

    Problem to_problem(ProblemCode code, std::string detail) const;

private:
    std::size_t reporting_cap_;
    std::size_t count_ = 0;
    std::vector<FieldError> reported_;
    std::set<std::string, std::less<>> pointers_;
};

// "object", "array", "string", "boolean", "number", "null"
std::string_view json_type_name(const nlohmann::json& value);

// Client text quoted in a message, shortened so a huge key cannot bloat the response.
std::string quoted_for_message(std::string_view text);

// true if `value` is an object; otherwise records "must be an object".
bool require_object(const nlohmann::json& value, const std::string& pointer, FieldErrors& errors);

// Explains a name that is not a field but looks like one a client would try ("k4").
using UnknownFieldHint = std::function<std::optional<std::string>(std::string_view name)>;

// Records every member of `object` whose name is not in `known`, with a hint or a suggestion.
void reject_unknown_fields(const nlohmann::json& object, const std::string& pointer,
                           std::span<const std::string_view> known, FieldErrors& errors,
                           const UnknownFieldHint& hint = nullptr);

// Each reader returns the value if it has the right type and lies in its bounds, else records
// the violation and returns nothing. Non-finite numbers (only possible when the JSON was built
// in code, the parser rejects them) are violations too.
std::optional<double> read_number(const nlohmann::json& value, const std::string& pointer,
                                  const Interval& range, Unit unit, FieldErrors& errors);
std::optional<long long> read_integer(const nlohmann::json& value, const std::string& pointer,
                                      const Interval& range, bool even, FieldErrors& errors);
std::optional<bool> read_boolean(const nlohmann::json& value, const std::string& pointer,
                                 FieldErrors& errors);
std::optional<std::string> read_choice(const nlohmann::json& value, const std::string& pointer,
                                       std::span<const std::string_view> choices,
                                       FieldErrors& errors);
std::optional<std::string> read_string(const nlohmann::json& value, const std::string& pointer,
                                       FieldErrors& errors);

std::string choices_text(std::span<const std::string_view> choices);  // "mixed | coulomb"

}  // namespace rollgap::api
