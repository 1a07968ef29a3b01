#include "upgrade_policy.hpp"

#include <penumbra/base/secret.hpp>

#include <algorithm>
#include <cctype>

namespace penumbra::net {
namespace {

int hex_value(char c) {
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    const char lower = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (lower >= 'a' && lower <= 'f') {
        return lower - 'a' + 10;
    }
    return -1;
}

// application/x-www-form-urlencoded: %XX escapes, '+' for a space.
std::optional<std::string> percent_decode(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] == '+') {
            out += ' ';
        } else if (text[i] == '%') {
            if (i + 2 >= text.size()) {
                return std::nullopt;
            }
            const int high = hex_value(text[i + 1]);
            const int low = hex_value(text[i + 2]);
            if (high < 0 || low < 0) {
                return std::nullopt;
            }
            out += static_cast<char>(high * 16 + low);
            i += 2;
        } else {
            out += text[i];
        }
    }
    return out;
}

std::string lower_case(std::string_view text) {
    std::string out(text);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

// "https://Example.org:8443" -> "example.org:8443"; an Origin without "://" (the opaque "null")
// has no authority and is nothing.
std::optional<std::string> authority_of(std::string_view origin) {
    const auto scheme_end = origin.find("://");
    if (scheme_end == std::string_view::npos) {
        return std::nullopt;
    }
    std::string_view rest = origin.substr(scheme_end + 3);
    rest = rest.substr(0, rest.find('/'));
    return lower_case(rest);
}

}  // namespace

std::optional<RequestTarget> parse_request_target(std::string_view target) {
    RequestTarget out;
    const auto question = target.find('?');
    out.path = std::string(target.substr(0, question));
    if (question == std::string_view::npos) {
        return out;
    }
    std::string_view query = target.substr(question + 1);
    query = query.substr(0, query.find('#'));
    while (!query.empty()) {
        const auto amp = query.find('&');
        const std::string_view pair = query.substr(0, amp);
        query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
        if (pair.empty()) {
            continue;
        }
        const auto equals = pair.find('=');
        auto name = percent_decode(pair.substr(0, equals));
        auto value = percent_decode(equals == std::string_view::npos ? std::string_view()
                                                                     : pair.substr(equals + 1));
        if (!name || !value) {
            return std::nullopt;
        }
        out.query.try_emplace(std::move(*name), std::move(*value));
    }
    return out;
}

base::Status check_upgrade(const UpgradePolicy& policy, std::optional<std::string_view> origin,
                           std::string_view host, const RequestTarget& target) {
    if (origin) {
        const auto& allowed = policy.allowed_origins;
        const bool listed =
                std::find(allowed.begin(), allowed.end(), "*") != allowed.end() ||
                std::any_of(allowed.begin(), allowed.end(), [&](const std::string& entry) {
                    return lower_case(entry) == lower_case(*origin);
                });
        const auto authority = authority_of(*origin);
        const bool same_origin = authority && !host.empty() && *authority == lower_case(host);
        if (!listed && !same_origin) {
            return base::make_error(base::ErrorCode::forbidden_origin,
                                    "a page from " + std::string(*origin) +
                                            " may not open this server's WebSocket (see "
                                            "--allowed-origins)",
                                    "Origin");
        }
    }
    if (!policy.access_token.empty()) {
        const auto token = target.query.find("token");
        if (token == target.query.end() || !base::same_secret(token->second, policy.access_token)) {
            return base::make_error(base::ErrorCode::unauthorized,
                                    token == target.query.end()
                                            ? "the WebSocket URL carries no access token (?token=)"
                                            : "wrong access token",
                                    "token");
        }
    }
    return base::Ok{};
}

}  // namespace penumbra::net
