#include "api/bite_options_json.h"

#include <array>
#include <string_view>

#include "api/option_table.h"
#include "api/options_reader.h"

namespace rollgap::api {

core::BiteOptions bite_options_from_json(const nlohmann::json& options, const std::string& pointer,
                                         FieldErrors& errors) {
    core::BiteOptions parsed;
    // neutral_point_guess is not offered: it only speeds up repeated solves inside the service.
    static constexpr std::array<std::string_view, 1> known{option_name(OptionId::distributions)};
    const OptionsReader reader(options, pointer, known, errors);
    reader.read(OptionId::distributions, parsed.distributions);
    return parsed;
}

nlohmann::json bite_options_json(const core::BiteOptions& options) {
    nlohmann::json document = nlohmann::json::object();
    put_option(document, OptionId::distributions, options.distributions);
    return document;
}

}  // namespace rollgap::api
