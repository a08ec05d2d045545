#include "api/bite_options_json.h"

#include <array>
#include <string_view>

#include "api/json_pointer.h"

namespace rollgap::api {

core::BiteOptions bite_options_from_json(const nlohmann::json& options, const std::string& pointer,
                                         FieldErrors& errors) {
    core::BiteOptions parsed;
    if (!require_object(options, pointer, errors)) return parsed;
    // neutral_point_guess is not offered: it only speeds up repeated solves inside the service.
    static constexpr std::array<std::string_view, 1> known{"distributions"};
    reject_unknown_fields(options, pointer, known, errors);
    if (const auto value = options.find("distributions"); value != options.end()) {
        if (const auto flag =
                read_boolean(*value, append_pointer(pointer, "distributions"), errors)) {
            parsed.distributions = *flag;
        }
    }
    return parsed;
}

nlohmann::json bite_options_json(const core::BiteOptions& options) {
    return {{"distributions", options.distributions}};
}

}  // namespace rollgap::api
