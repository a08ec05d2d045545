#include "api/json_text.h"

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "api/field_errors.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

// Thrown from inside the parser callback to stop parsing at the first structural violation.
struct RejectedStructure {
    std::string reason;
};

}  // namespace

std::variant<nlohmann::json, Problem> parse_json_text(std::string_view text) {
    // Key sets of the objects currently open, innermost last (arrays hold no keys).
    std::vector<std::set<std::string, std::less<>>> open_objects;
    const auto check_structure = [&open_objects](int depth, nlohmann::json::parse_event_t event,
                                                 nlohmann::json& parsed) {
        using Event = nlohmann::json::parse_event_t;
        switch (event) {
            case Event::object_start:
            case Event::array_start:
                if (depth >= max_json_depth) {
                    throw RejectedStructure{
                        concat("nesting deeper than ", std::to_string(max_json_depth), " levels")};
                }
                if (event == Event::object_start) open_objects.emplace_back();
                break;
            case Event::key: {
                auto& keys = open_objects.back();
                auto name = parsed.get<std::string>();
                if (!keys.insert(name).second) {
                    throw RejectedStructure{concat("duplicate key ", quoted_for_message(name))};
                }
                break;
            }
            case Event::object_end: open_objects.pop_back(); break;
            case Event::array_end:
            case Event::value: break;
        }
        return true;
    };
    try {
        return nlohmann::json::parse(text.begin(), text.end(), check_structure);
    } catch (const RejectedStructure& rejected) {
        return make_problem(ProblemCode::invalid_json,
                            concat("request body has ", rejected.reason));
    } catch (const nlohmann::json::exception& error) {
        // parse_error (syntax, with the position) or out_of_range 406 (number overflow). The
        // message starts with an internal tag, "[json.exception.parse_error.101] ", dropped here.
        std::string_view message = error.what();
        if (const auto tag_end = message.find("] ");
            !message.empty() && message.front() == '[' && tag_end != std::string_view::npos) {
            message.remove_prefix(tag_end + 2);
        }
        return make_problem(ProblemCode::invalid_json, std::string(message));
    }
}

bool nests_deeper_than(const nlohmann::json& value, int max_depth) {
    std::vector<std::pair<const nlohmann::json*, int>> pending{{&value, 0}};
    while (!pending.empty()) {
        const auto [node, depth] = pending.back();
        pending.pop_back();
        if (!node->is_structured()) continue;
        if (depth + 1 > max_depth) return true;
        for (const auto& child : *node) pending.emplace_back(&child, depth + 1);
    }
    return false;
}

}  // namespace rollgap::api
