#include "api/options_reader.h"

#include <cassert>

#include "api/json_pointer.h"

namespace rollgap::api {

OptionsReader::OptionsReader(const nlohmann::json& options, std::string pointer,
                             std::span<const std::string_view> known, FieldErrors& errors)
    : pointer_(std::move(pointer)), errors_(errors) {
    if (!require_object(options, pointer_, errors_)) return;
    object_ = &options;
    reject_unknown_fields(options, pointer_, known, errors_);
}

std::string OptionsReader::at(std::string_view name) const {
    return append_pointer(pointer_, name);
}

const nlohmann::json* OptionsReader::find(std::string_view name) const {
    if (object_ == nullptr) return nullptr;
    const auto member = object_->find(std::string(name));
    return member == object_->end() ? nullptr : &*member;
}

const nlohmann::json& OptionsReader::object_or_defaults(std::string_view name) const {
    static const nlohmann::json empty = nlohmann::json::object();
    const nlohmann::json* member = find(name);
    return member == nullptr || member->is_null() ? empty : *member;
}

bool OptionsReader::number(std::string_view name, Unit unit, const Interval& range,
                           double& si_target) const {
    const nlohmann::json* value = find(name);
    if (value == nullptr) return false;
    const auto number = read_number(*value, at(name), range, unit, errors_);
    if (!number) return false;
    si_target = to_si(*number, unit);
    return true;
}

bool OptionsReader::integer(std::string_view name, const Interval& range, int& target) const {
    const nlohmann::json* value = find(name);
    if (value == nullptr) return false;
    const auto integer = read_integer(*value, at(name), range, false, errors_);
    if (!integer) return false;
    target = static_cast<int>(*integer);  // within range: callers' ranges fit an int
    return true;
}

bool OptionsReader::boolean(std::string_view name, bool& target) const {
    const nlohmann::json* value = find(name);
    if (value == nullptr) return false;
    const auto flag = read_boolean(*value, at(name), errors_);
    if (!flag) return false;
    target = *flag;
    return true;
}

bool OptionsReader::read(OptionId id, double& si_target) const {
    const Option& row = option(id);
    assert(row.type == OptionType::number);
    return number(row.name, row.unit, row.range, si_target);
}

bool OptionsReader::read(OptionId id, int& target) const {
    const Option& row = option(id);
    assert(row.type == OptionType::integer);
    return integer(row.name, row.range, target);
}

bool OptionsReader::read(OptionId id, bool& target) const {
    const Option& row = option(id);
    assert(row.type == OptionType::boolean);
    return boolean(row.name, target);
}

void put_option(nlohmann::json& document, OptionId id, double value_si) {
    const Option& row = option(id);
    assert(row.type == OptionType::number);
    document[std::string(row.name)] = echo(value_si, row.unit);
}

void put_option(nlohmann::json& document, OptionId id, int value) {
    assert(option(id).type == OptionType::integer);
    document[std::string(option_name(id))] = value;
}

void put_option(nlohmann::json& document, OptionId id, bool value) {
    assert(option(id).type == OptionType::boolean);
    document[std::string(option_name(id))] = value;
}

}  // namespace rollgap::api
