#include "api/tandem_options_json.h"

#include <string_view>
#include <vector>

#include "api/option_table.h"
#include "api/options_reader.h"
#include "api/text.h"

namespace rollgap::api {

TandemOptions tandem_options_from_json(const nlohmann::json& options, const std::string& pointer,
                                       int stands, FieldErrors& errors) {
    std::vector<std::string_view> members(stability_option_members().begin(),
                                          stability_option_members().end());
    for (const OptionId id :
         {OptionId::mill_time_series, OptionId::mill_window, OptionId::time_series_points,
          OptionId::kick_gap, OptionId::kick_stand})
        members.push_back(option_name(id));
    const OptionsReader reader(options, pointer, members, errors);
    TandemOptions parsed;
    parsed.stability = read_stability_options(reader);
    reader.read(OptionId::mill_time_series, parsed.time_series);
    reader.read(OptionId::mill_window, parsed.window);
    if (reader.read(OptionId::time_series_points, parsed.time_series_points) && stands > 0 &&
        parsed.time_series_points * stands > max_mill_time_series_values) {
        // Every stand's series is as long: the answer's size is points x stands.
        const int most = max_mill_time_series_values / stands;
        errors.add(
            {reader.at(option_name(OptionId::time_series_points)),
             concat(std::to_string(parsed.time_series_points), " points x ", std::to_string(stands),
                    " stands exceeds the ", std::to_string(max_mill_time_series_values),
                    " points a mill's time series may hold; at most ", std::to_string(most),
                    " for this mill"),
             concat("[2, ", std::to_string(most), "]"), std::nullopt});
    }
    reader.read(OptionId::kick_gap, parsed.kick);
    if (reader.read(OptionId::kick_stand, parsed.kick_stand) && stands > 0 &&
        parsed.kick_stand > stands) {
        errors.add({reader.at(option_name(OptionId::kick_stand)),
                    concat("this mill has ", std::to_string(stands), " stands; kick_stand ",
                           std::to_string(parsed.kick_stand), " is none of them"),
                    concat("[0, ", std::to_string(stands), "]"), std::nullopt});
    }
    return parsed;
}

nlohmann::json tandem_options_json(const TandemOptions& options) {
    nlohmann::json document = stability_options_json(options.stability);
    put_option(document, OptionId::mill_time_series, options.time_series);
    put_option(document, OptionId::mill_window, options.window);
    put_option(document, OptionId::time_series_points, options.time_series_points);
    put_option(document, OptionId::kick_gap, options.kick);
    put_option(document, OptionId::kick_stand, options.kick_stand);
    return document;
}

}  // namespace rollgap::api
