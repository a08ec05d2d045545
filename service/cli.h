#pragma once
// The command line, as a function of its arguments and streams so that tests run it in
// process. Exit status: 0 success, 1 internal error, 2 bad input or bad usage.

#include <functional>
#include <iosfwd>
#include <span>
#include <string>
#include <string_view>

#include "service/config.h"

namespace rollgap::service {

inline constexpr int exit_success = 0;
inline constexpr int exit_internal_error = 1;
inline constexpr int exit_bad_input = 2;

// The commands that speak HTTP (`serve`, `healthcheck`) live in the HTTP layer (rollgap_http),
// the only code that links httplib; the executable hands them in, so this library does not
// depend on that layer. Without them the two commands answer that this build has no HTTP layer.
struct ServerCommands {
    std::function<int(const ServerConfig& config)> serve;
    std::function<int(const std::string& url, std::ostream& out, std::ostream& err)> healthcheck;
};

// `arguments` excludes the program name.
int run_cli(std::span<const std::string_view> arguments, std::istream& in, std::ostream& out,
            std::ostream& err, const ServerCommands& server = {});

}  // namespace rollgap::service
