#pragma once
// The subcommands of `rollgap` that belong to the HTTP service:
//   rollgap serve [OPTION VALUE]...   run the service until SIGTERM/SIGINT, then drain, exit 0
//   rollgap healthcheck [--url URL]   exit 0 iff URL (default http://127.0.0.1:$ROLLGAP_ADMIN_PORT/readyz,
//                                     the admin listener)
//                                     answers 200: the container's HEALTHCHECK, no curl needed
//   rollgap openapi                   print the OpenAPI document served at /openapi.json
// Exit status: 0 success, 1 failure (cannot listen, not healthy), 2 bad usage.

#include <iosfwd>
#include <span>
#include <string_view>

namespace rollgap::service {

bool is_server_command(std::string_view command);

// `arguments` starts with the subcommand.
int run_server_command(std::span<const std::string_view> arguments, std::ostream& out, std::ostream& err);

}  // namespace rollgap::service
