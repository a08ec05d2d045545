#pragma once
// The subcommands of `rollgap` that belong to the HTTP service, after the command line is parsed
// (service/cli.cpp):
//   rollgap serve [OPTION VALUE]...   run the service until SIGTERM/SIGINT, then drain, exit 0
//   rollgap healthcheck [--url URL]   exit 0 iff URL (default
//   http://127.0.0.1:$ROLLGAP_ADMIN_PORT/readyz,
//                                     the admin listener)
//                                     answers 200: the container's HEALTHCHECK, no curl needed
// Exit status: 0 success, 1 failure (cannot listen, not healthy), 2 bad usage.

#include <iosfwd>
#include <string>

#include "service/config.h"

namespace rollgap::service {

// Runs the service with `config` (as parsed, resolved here) until SIGTERM/SIGINT.
int serve(const ServerConfig& config);

int healthcheck(const std::string& url, std::ostream& out, std::ostream& err);

}  // namespace rollgap::service
