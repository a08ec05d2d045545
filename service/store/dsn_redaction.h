#pragma once
// Secrets never reach a log line or a problem: the store setting as logs show it, and any text
// that went through libpq with a DSN (its errors quote what they refuse) with the DSN's secrets
// taken out. In the store library because both the store (its error details) and the service's
// start-up line need it.

#include <string>
#include <string_view>

namespace rollgap::service::store {

// The store setting for logs: a DSN's user, password and parameters left out; when the host
// cannot be told apart from the user info for sure (a raw `/`, `?` or `@` in a password, an
// `@` in the query), the DSN is shown as `postgresql://…` alone.
std::string redacted_store(std::string_view setting);

// `text` (a libpq error, an exception's message) with every secret of a DSN taken out: each
// `postgres(ql)://…` DSN it holds (as redacted_store() shows it), each `password=` value
// (key=value form, quoted or not), and, when the DSN `dsn` that produced the text is given,
// every double-quoted value that echoes a piece of its user info or password (libpq quotes
// what it refuses: `invalid percent-encoded token: "pa%zz"`, a password read as a port). Call
// it on any text that reaches a log or a problem after a DSN went through libpq.
std::string redact_dsn_secrets(std::string_view text, std::string_view dsn = {});

}  // namespace rollgap::service::store
