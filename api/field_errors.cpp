#include "api/field_errors.h"

#include <algorithm>
#include <cmath>

#include "api/json_pointer.h"
#include "api/name_suggestion.h"
#include "api/text.h"

namespace rollgap::api {

FieldErrors::FieldErrors(std::size_t reporting_cap) : reporting_cap_(reporting_cap) {}

void FieldErrors::add(FieldError error) {
    ++count_;
    pointers_.insert(error.pointer);
    if (reported_.size() < reporting_cap_) reported_.push_back(std::move(error));
}

bool FieldErrors::has_error_at_or_below(std::string_view pointer) const {
    for (auto it = pointers_.lower_bound(pointer); it != pointers_.end(); ++it) {
        const std::string_view candidate = *it;
        if (candidate.substr(0, pointer.size()) != pointer) break;  // sorted: past the prefix
        if (candidate.size() == pointer.size() || candidate[pointer.size()] == '/') return true;
    }
    return false;
}

Problem FieldErrors::to_problem(ProblemCode code, std::string detail) const {
    Problem problem = make_problem(code, std::move(detail), reported_);
    problem.errors_omitted = count_ - reported_.size();
    return problem;
}

std::string_view json_type_name(const nlohmann::json& value) {
    switch (value.type()) {
        case nlohmann::json::value_t::object: return "object";
        case nlohmann::json::value_t::array: return "array";
        case nlohmann::json::value_t::string: return "string";
        case nlohmann::json::value_t::boolean: return "boolean";
        case nlohmann::json::value_t::number_integer:
        case nlohmann::json::value_t::number_unsigned:
        case nlohmann::json::value_t::number_float: return "number";
        case nlohmann::json::value_t::null: return "null";
        case nlohmann::json::value_t::binary: return "binary";
        case nlohmann::json::value_t::discarded: return "discarded";
    }
    return "unknown";
}

std::string quoted_for_message(std::string_view text) {
    constexpr std::size_t longest_quoted = 80;
    if (text.size() <= longest_quoted) return concat("'", text, "'");
    return concat("'", text.substr(0, longest_quoted), "...'");
}

namespace {

void add_type_error(const nlohmann::json& value, const std::string& pointer,
                    std::string_view expected, FieldErrors& errors) {
    errors.add({pointer, concat("must be ", expected, ", got ", json_type_name(value)),
                std::nullopt, std::nullopt});
}

}  // namespace

bool require_object(const nlohmann::json& value, const std::string& pointer, FieldErrors& errors) {
    if (value.is_object()) return true;
    add_type_error(value, pointer, "an object", errors);
    return false;
}

void reject_unknown_fields(const nlohmann::json& object, const std::string& pointer,
                           std::span<const std::string_view> known, FieldErrors& errors,
                           const UnknownFieldHint& hint) {
    for (const auto& [name, value] : object.items()) {
        if (std::find(known.begin(), known.end(), name) != known.end()) continue;
        if (errors.reporting_full()) {  // only counted: skip the suggestion search
            errors.add(
                {append_pointer(pointer, name), "unknown field", std::nullopt, std::nullopt});
            continue;
        }
        std::string detail = concat("unknown field ", quoted_for_message(name));
        if (auto explanation = hint ? hint(name) : std::nullopt) {
            errors.add({append_pointer(pointer, name), concat(detail, ": ", *explanation),
                        std::nullopt, std::nullopt});
            continue;
        }
        detail += did_you_mean(name, known);
        detail += " (known fields:";
        for (const std::string_view field : known) detail += concat(" ", field);
        detail += ")";
        errors.add({append_pointer(pointer, name), std::move(detail), std::nullopt, std::nullopt});
    }
}

std::optional<double> read_number(const nlohmann::json& value, const std::string& pointer,
                                  const Interval& range, Unit unit, FieldErrors& errors) {
    if (!value.is_number()) {
        add_type_error(value, pointer, "a number", errors);
        return std::nullopt;
    }
    const double number = value.get<double>();
    if (!std::isfinite(number)) {
        errors.add({pointer, "must be a finite number", range.text(), std::string(unit.code)});
        return std::nullopt;
    }
    if (!range.contains(number)) {
        // Dimensionless values read better without the unit code "1".
        const std::string unit_suffix = unit.code == units::one.code ? "" : concat(" ", unit.code);
        std::string detail =
            concat(format_number(number), unit_suffix, " is outside ", range.text(), unit_suffix);
        // A fraction given as a percentage ("reduction": 25): say so when value / 100 would fit.
        if (unit.code == units::one.code && range.max <= 1.0 && number > 1.0 &&
            range.contains(number / 100.0)) {
            detail += concat("; this is a fraction, 0.25 = 25 %: for ", format_number(number),
                             " % write ", format_number(number / 100.0));
        }
        errors.add({pointer, std::move(detail), range.text(), std::string(unit.code)});
        return std::nullopt;
    }
    return number + 0.0;  // -0 → 0, so the echo does not show "-0.0"
}

std::optional<long long> read_integer(const nlohmann::json& value, const std::string& pointer,
                                      const Interval& range, bool even, FieldErrors& errors) {
    const std::string bound = concat(range.text(), even ? ", even" : "");
    if (!value.is_number()) {
        add_type_error(value, pointer, "an integer", errors);
        return std::nullopt;
    }
    // 64.0 (a float in JSON from some clients) is accepted; 64.5 is not.
    const double number = value.get<double>();
    if (!std::isfinite(number) || std::trunc(number) != number) {
        errors.add({pointer, "must be an integer", bound, "1"});
        return std::nullopt;
    }
    if (!range.contains(number) || (even && std::fmod(number, 2.0) != 0.0)) {
        errors.add({pointer, concat(format_number(number), " is outside ", bound), bound, "1"});
        return std::nullopt;
    }
    return static_cast<long long>(number);
}

std::optional<bool> read_boolean(const nlohmann::json& value, const std::string& pointer,
                                 FieldErrors& errors) {
    if (!value.is_boolean()) {
        add_type_error(value, pointer, "a boolean", errors);
        return std::nullopt;
    }
    return value.get<bool>();
}

std::optional<std::string> read_string(const nlohmann::json& value, const std::string& pointer,
                                       FieldErrors& errors) {
    if (!value.is_string()) {
        add_type_error(value, pointer, "a string", errors);
        return std::nullopt;
    }
    return value.get<std::string>();
}

std::optional<std::string> read_choice(const nlohmann::json& value, const std::string& pointer,
                                       std::span<const std::string_view> choices,
                                       FieldErrors& errors) {
    if (!value.is_string()) {
        add_type_error(value, pointer, concat("one of the strings ", choices_text(choices)),
                       errors);
        return std::nullopt;
    }
    const auto& text = value.get_ref<const std::string&>();
    if (std::find(choices.begin(), choices.end(), text) == choices.end()) {
        std::string detail =
            concat(quoted_for_message(text), " is not one of ", choices_text(choices));
        detail += did_you_mean(text, choices);
        errors.add({pointer, std::move(detail), choices_text(choices), std::nullopt});
        return std::nullopt;
    }
    return text;
}

std::string choices_text(std::span<const std::string_view> choices) {
    std::string text;
    for (const std::string_view choice : choices) {
        if (!text.empty()) text += " | ";
        text += choice;
    }
    return text;
}

}  // namespace rollgap::api
