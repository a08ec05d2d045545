#pragma once
// Message building. concat() appends into one string instead of chaining operator+, which
// also sidesteps GCC 12's false -Wrestrict on `"literal" + std::string` at -O2 (GCC PR 105329),
// fatal under -Werror.

#include <string>
#include <string_view>

namespace rollgap::api {

template <class... Parts>
std::string concat(const Parts&... parts) {
    std::string text;
    text.reserve((std::string_view(parts).size() + ...));
    (text.append(std::string_view(parts)), ...);
    return text;
}

}  // namespace rollgap::api
