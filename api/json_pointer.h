#pragma once
// RFC 6901 JSON pointers for error locations. Object keys come from the client and may
// contain '/' or '~', which must be escaped or the pointer would name another field.

#include <string>
#include <string_view>

namespace rollgap::api {

std::string escape_pointer_token(std::string_view token);  // "~" → "~0", "/" → "~1"

// "/scenario" + "strip" → "/scenario/strip"
std::string append_pointer(std::string_view pointer, std::string_view token);

}  // namespace rollgap::api
