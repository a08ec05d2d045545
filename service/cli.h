#pragma once
// The command line, as a function of its arguments and streams so that tests run it in
// process. Exit status: 0 success, 1 internal error, 2 bad input or bad usage.

#include <iosfwd>
#include <span>
#include <string_view>

namespace rollgap::service {

inline constexpr int exit_success = 0;
inline constexpr int exit_internal_error = 1;
inline constexpr int exit_bad_input = 2;

// `arguments` excludes the program name.
int run_cli(std::span<const std::string_view> arguments, std::istream& in, std::ostream& out,
            std::ostream& err);

}  // namespace rollgap::service
