#pragma once

#include <string_view>

namespace rollgap::service {

// The project version from CMake (project(rollgap VERSION ...)).
std::string_view version();

}  // namespace rollgap::service
