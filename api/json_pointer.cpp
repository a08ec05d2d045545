#include "api/json_pointer.h"

namespace rollgap::api {

std::string escape_pointer_token(std::string_view token) {
    std::string escaped;
    escaped.reserve(token.size());
    for (const char c : token) {
        if (c == '~') {
            escaped += "~0";
        } else if (c == '/') {
            escaped += "~1";
        } else {
            escaped += c;
        }
    }
    return escaped;
}

std::string append_pointer(std::string_view pointer, std::string_view token) {
    std::string result(pointer);
    result += '/';
    result += escape_pointer_token(token);
    return result;
}

}  // namespace rollgap::api
