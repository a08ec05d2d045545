#include "api/options_reader.h"

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

}  // namespace rollgap::api
