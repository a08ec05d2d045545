#include "service/analyses/roll_gap.h"

#include "api/bite_options_json.h"
#include "api/result_json.h"
#include "core/roll_bite.h"

namespace rollgap::service {

PreparedAnalysis prepare_roll_gap(const core::Scenario& scenario, const nlohmann::json& options,
                                  const std::string& options_pointer, api::FieldErrors& errors) {
    const core::BiteOptions bite_options =
        api::bite_options_from_json(options, options_pointer, errors);
    return {
        api::bite_options_json(bite_options),
        [scenario, bite_options] {
            const core::BiteResult result =
                core::solve_roll_bite(scenario, core::steady_bite_state(scenario), bite_options);
            return api::bite_result_json(result);
        },
    };
}

}  // namespace rollgap::service
