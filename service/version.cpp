#include "service/version.h"

#ifndef ROLLGAP_VERSION
#error "ROLLGAP_VERSION must be defined by the build (service/CMakeLists.txt)"
#endif

namespace rollgap::service {

std::string_view version() { return ROLLGAP_VERSION; }

}  // namespace rollgap::service
