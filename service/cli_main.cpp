// rollgap: the command-line front end of the service (service/cli.h).

#include <iostream>
#include <string_view>
#include <vector>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "service/cli.h"
#include "service/http/serve_main.h"

int main(int argc, char** argv) {
    // stdout carries the JSON document; diagnostics go to stderr.
    spdlog::set_default_logger(spdlog::stderr_color_mt("rollgap"));
    const std::vector<std::string_view> arguments(argv + 1, argv + argc);
    return rollgap::service::run_cli(arguments, std::cin, std::cout, std::cerr,
                                     {rollgap::service::serve, rollgap::service::healthcheck});
}
