// A DSN's secrets never reach a log line or a problem: the start-up line shows the store as
// redacted_store() does, and whatever libpq says about a DSN it refused goes through
// redact_dsn_secrets() first (issue 16, item 4). The libpq texts here are real: each DSN is
// handed to open_store(), which connects to a closed port on loopback (fails at once).

#include "service/config.h"
#include "service/store/job_store.h"

#include <doctest/doctest.h>

#include <string>
#include <vector>

using namespace rollgap::service;

namespace {

struct Form {
    std::string dsn;
    std::vector<std::string> secrets;  // none of these may be shown
    std::string shown;                 // what redacted_store() shows
};

// Port 1 on loopback: nothing listens there, so libpq answers without waiting.
const std::vector<Form>& forms() {
    static const std::vector<Form> all{
        {"postgresql://rg:plain-secret@127.0.0.1:1/db",
         {"plain-secret", "rg:"},
         "postgresql://…@127.0.0.1:1"},
        {"postgres://rg:pa/ss-word@127.0.0.1:1/db",
         {"pa/ss", "ss-word", "\"pa\""},
         "postgres://…@127.0.0.1:1"},
        {"postgresql://rg:pa?ss-word@127.0.0.1:1/db",
         {"pa?ss", "ss-word", "rg:pa"},
         "postgresql://…"},
        {"postgresql://rg:p@ss-word@127.0.0.1:1/db",
         {"p@ss", "ss-word"},
         "postgresql://…@127.0.0.1:1"},
        {"postgresql://rg:pa%zzss-word@127.0.0.1:1/db",
         {"pa%zz", "zzss", "ss-word"},
         "postgresql://…@127.0.0.1:1"},
        {"postgresql://rg:se%2Gcret-word@127.0.0.1:1/db",
         {"se%2G", "cret-word"},
         "postgresql://…@127.0.0.1:1"},
        {"postgresql://127.0.0.1:1/db?user=rg&password=query-secret",
         {"query-secret"},
         "postgresql://…@127.0.0.1:1"},
        {"postgresql://127.0.0.1:1/db?password=qu@ery-secret",
         {"qu@ery", "ery-secret"},
         "postgresql://…"},
        {"postgresql://rg:a%20b%2Fsecret@127.0.0.1:1/db",
         {"a%20b", "2Fsecret", "b/secret"},
         "postgresql://…@127.0.0.1:1"},
    };
    return all;
}

bool shows_any(const std::string& text, const std::vector<std::string>& secrets) {
    for (const std::string& secret : secrets) {
        if (text.find(secret) != std::string::npos) return true;
    }
    return false;
}

}  // namespace

TEST_CASE("DSN redaction: the start-up line shows no part of a password, whatever the DSN form") {
    for (const Form& form : forms()) {
        CAPTURE(form.dsn);
        const std::string shown = redacted_store(form.dsn);
        CHECK(shown == form.shown);
        CHECK_FALSE(shows_any(shown, form.secrets));
        ServerConfig config;
        config.store = form.dsn;
        CHECK_FALSE(shows_any(describe(config), form.secrets));
    }
    CHECK(redacted_store("sqlite:/var/lib/rollgap/jobs.db") == "sqlite:/var/lib/rollgap/jobs.db");
    CHECK(redacted_store("postgresql-file:/run/secrets/dsn") == "postgresql-file:/run/secrets/dsn");
    CHECK(redacted_store("postgresql://db.example:5432/jobs") == "postgresql://…@db.example:5432");
}

TEST_CASE("DSN redaction: libpq's error text about a DSN keeps none of its secrets") {
    for (const Form& form : forms()) {
        CAPTURE(form.dsn);
        // open_store's detail is what the service logs: already without the DSN's secrets.
        const auto opened = store::open_store(form.dsn);
        REQUIRE_FALSE(opened.ok());
        CAPTURE(opened.detail);
        CHECK_FALSE(shows_any(opened.detail, form.secrets));
        CHECK_FALSE(opened.detail.empty());
    }
}

TEST_CASE("DSN redaction: any text, with DSNs and key=value passwords in it") {
    // A DSN of every form quoted in a message, without knowing which DSN it was.
    CHECK(redact_dsn_secrets("cannot open postgresql://u:pw-one@h:5/db now") ==
          "cannot open postgresql://…@h:5 now");
    CHECK(redact_dsn_secrets("a 'postgres://u:p/w-two@h/db' b") == "a 'postgres://…@h' b");
    CHECK(redact_dsn_secrets("x=\"postgresql://u:p?w@h/db\"") == "x=\"postgresql://…\"");
    // key=value connection strings: plain, quoted with blanks and escapes, any case.
    CHECK(redact_dsn_secrets("host=h password=kv-secret user=u") == "host=h password=… user=u");
    CHECK(redact_dsn_secrets("host=h password = 'kv se\\'cret' user=u") ==
          "host=h password=… user=u");
    CHECK(redact_dsn_secrets("host=h PASSWORD=KvSecret") == "host=h PASSWORD=…");
    // With the DSN known: its whole text (even with a raw blank in it) and the quoted pieces.
    const std::string blank = "postgresql://u:two words@h/db";
    CHECK(redact_dsn_secrets("failed: " + blank, blank).find("words") == std::string::npos);
    CHECK(
        redact_dsn_secrets("invalid integer value \"two\" for connection option \"port\"", blank) ==
        "invalid integer value \"…\" for connection option \"port\"");
    // Text with nothing secret stays as it is.
    CHECK(redact_dsn_secrets("connection refused") == "connection refused");
}
