// Secrets out of DSNs and of the texts libpq writes about them (dsn_redaction.h).

#include "service/store/dsn_redaction.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <string>
#include <vector>

namespace rollgap::service::store {

namespace {

constexpr std::array<std::string_view, 2> dsn_schemes{"postgresql://", "postgres://"};

bool host_character(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '.' || c == '-' || c == '_' ||
           c == ':' || c == '[' || c == ']' || c == ',' || c == '%';
}

// The user info of a URI DSN, conservatively: everything between the scheme and its last `@`
// (a raw `@`, `/` or `?` in a password is not escaped by everyone); empty without an `@`.
std::string_view user_info(std::string_view dsn) {
    for (const std::string_view scheme : dsn_schemes) {
        if (!dsn.starts_with(scheme)) continue;
        const std::string_view rest = dsn.substr(scheme.size());
        const auto at = rest.rfind('@');
        return at == std::string_view::npos ? std::string_view() : rest.substr(0, at);
    }
    return {};
}

bool is_space_or_quote(char c) {
    return std::isspace(static_cast<unsigned char>(c)) != 0 || c == '"' || c == '\'';
}

// The value of every `password=` (case-insensitive) in `text`, key=value form: up to the next
// blank, or a quoted value with its backslash escapes.
std::string redact_password_values(std::string_view text) {
    std::string out;
    std::size_t i = 0;
    const std::string lower_text = [&] {
        std::string l(text);
        for (char& c : l) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        return l;
    }();
    while (i < text.size()) {
        const auto found = lower_text.find("password", i);
        if (found == std::string::npos) break;
        std::size_t j = found + 8;
        while (j < text.size() && text[j] == ' ') ++j;
        if (j >= text.size() || text[j] != '=') {
            out.append(text.substr(i, j - i));
            i = j;
            continue;
        }
        ++j;
        while (j < text.size() && text[j] == ' ') ++j;
        out.append(text.substr(i, found + 8 - i));
        out += "=…";
        if (j < text.size() && text[j] == '\'') {
            ++j;
            while (j < text.size() && text[j] != '\'') j += text[j] == '\\' ? 2 : 1;
            i = std::min(j + 1, text.size());
        } else {
            while (j < text.size() && !std::isspace(static_cast<unsigned char>(text[j])) &&
                   text[j] != '&' && text[j] != '"')
                ++j;
            i = j;
        }
    }
    if (i < text.size()) out.append(text.substr(i));
    return out;
}

std::string percent_decoded(std::string_view text) {
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        int value = 0;
        if (text[i] == '%' && i + 2 < text.size() &&
            std::from_chars(text.data() + i + 1, text.data() + i + 3, value, 16).ptr ==
                text.data() + i + 3) {
            out += static_cast<char>(value);
            i += 2;
        } else {
            out += text[i];
        }
    }
    return out;
}

}  // namespace

std::string redacted_store(std::string_view setting) {
    for (const std::string_view scheme : dsn_schemes) {
        if (!setting.starts_with(scheme)) continue;
        const std::string_view rest = setting.substr(scheme.size());
        const auto at = rest.rfind('@');
        // An `@` after a `?` may be the query's (…?password=a@b) or a raw one in a password
        // (u:p?x@host): either way the host cannot be told for sure.
        const auto query = rest.find('?');
        if (at != std::string_view::npos && query != std::string_view::npos && query < at)
            return std::string(scheme) + "…";
        std::string_view host = at == std::string_view::npos ? rest : rest.substr(at + 1);
        host = host.substr(0, host.find_first_of("/?#"));
        // Without an `@` the part before the first `/` is the host; with one, a raw `/` in the
        // password has been skipped. Anything but host characters is shown as nothing.
        if (host.empty() || !std::all_of(host.begin(), host.end(), host_character))
            return std::string(scheme) + "…";
        return std::string(scheme) + "…@" + std::string(host);
    }
    return std::string(setting);  // sqlite:PATH or postgresql-file:PATH: no secret in it
}

std::string redact_dsn_secrets(std::string_view text, std::string_view dsn) {
    std::string out(text);
    // The DSN itself, wherever it is repeated whole (it may hold blanks a token would stop at).
    if (!dsn.empty()) {
        const std::string shown = redacted_store(dsn);
        for (auto at = out.find(dsn); at != std::string::npos;
             at = out.find(dsn, at + shown.size()))
            out.replace(at, dsn.size(), shown);
    }
    // Every other URI DSN, up to a blank or a quote.
    for (const std::string_view scheme : dsn_schemes) {
        std::size_t from = 0;
        for (auto at = out.find(scheme, from); at != std::string::npos;
             at = out.find(scheme, from)) {
            std::size_t end = at + scheme.size();
            while (end < out.size() && !is_space_or_quote(out[end])) ++end;
            const std::string shown = redacted_store(std::string_view(out).substr(at, end - at));
            out.replace(at, end - at, shown);
            from = at + shown.size();
        }
    }
    out = redact_password_values(out);
    // Double-quoted values that echo a piece of the DSN's user info (libpq quotes what it refuses).
    const std::string_view info = user_info(dsn);
    if (info.empty()) return out;
    std::vector<std::string> pieces;
    const auto add_pieces = [&pieces](std::string_view whole) {
        std::size_t begin = 0;
        for (std::size_t i = 0; i <= whole.size(); ++i) {
            if (i == whole.size() ||
                std::string_view(":/?@&=#").find(whole[i]) != std::string_view::npos) {
                if (i > begin) pieces.emplace_back(whole.substr(begin, i - begin));
                begin = i + 1;
            }
        }
    };
    add_pieces(info);
    add_pieces(percent_decoded(info));
    std::string result;
    std::size_t i = 0;
    while (i < out.size()) {
        const auto open = out.find('"', i);
        const auto close = open == std::string::npos ? open : out.find('"', open + 1);
        if (close == std::string::npos) break;
        const std::string_view quoted = std::string_view(out).substr(open + 1, close - open - 1);
        const bool echoes =
            (!quoted.empty() && std::string_view(info).find(quoted) != std::string_view::npos) ||
            std::any_of(pieces.begin(), pieces.end(), [quoted](const std::string& piece) {
                return piece.size() >= 2 && quoted.find(piece) != std::string_view::npos;
            });
        result.append(out, i, open + 1 - i);
        result += echoes ? "…" : std::string(quoted);
        result += '"';
        i = close + 1;
    }
    result.append(out, std::min(i, out.size()), std::string::npos);
    return result;
}

}  // namespace rollgap::service::store
