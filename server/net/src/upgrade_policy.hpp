#pragma once

#include <penumbra/base/result.hpp>

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::net {

// A request target split into its path and its query parameters, percent-decoded
// ("/ws?volume=ch2.nii.gz&token=a%2Bb" -> "/ws", {volume: ch2.nii.gz, token: a+b}). The first of
// repeated parameters counts. Nothing for a malformed percent escape.
struct RequestTarget {
    std::string path;
    std::map<std::string, std::string> query;
};

std::optional<RequestTarget> parse_request_target(std::string_view target);

// Who may open the WebSocket. Browsers send the page's Origin with the upgrade: it must be this
// server's own (scheme aside, its host and port are the Host the browser asked for) or one of
// `allowed_origins` ("*" allows any), so that a page of another site cannot drive a user's
// session. Clients that are not browsers send no Origin and are not concerned. With an
// `access_token`, the upgrade must also carry it as the `token` query parameter.
struct UpgradePolicy {
    std::vector<std::string> allowed_origins;
    std::string access_token;
};

// Ok, or forbidden_origin (field: the Origin) or unauthorized (a missing or wrong token).
base::Status check_upgrade(const UpgradePolicy& policy, std::optional<std::string_view> origin,
                           std::string_view host, const RequestTarget& target);

}  // namespace penumbra::net
