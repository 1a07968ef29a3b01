#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/protocol/limits.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <algorithm>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace penumbra::protocol {

// A `set` patch (a JSON object with any of "camera", "light", "transfer_function", "settings",
// "output"), parsed once and kept parsed: it is applied as it is, never printed and parsed again.
// The document's type stays inside this module.
class Patch {
public:
    struct Document;

    explicit Patch(std::shared_ptr<const Document> document);

    [[nodiscard]] const Document& document() const { return *document_; }

private:
    std::shared_ptr<const Document> document_;
};

// Parses a patch (depth-limited by `limits.max_json_depth`); it must be a JSON object. What it
// sets is checked when it is applied.
base::Result<Patch> parse_patch(std::string_view patch_json, const Limits& limits);

// Applies a patch onto `state`: each setting of scene's table (kSettings) at its path, the
// camera's view or orbit, the transfer function. Unknown fields, wrong types, non-finite numbers
// and values outside the limits are errors naming the JSON pointer of the field; on error `state`
// is unchanged.
base::Status apply_patch(const Patch& patch, scene::State& state, const Limits& limits);

// parse_patch, then apply_patch.
base::Status apply_patch(std::string_view patch_json, scene::State& state, const Limits& limits);

// The state as text, in the shape `set` accepts and `state` messages carry (the messages write
// it into themselves without this step).
std::string state_to_json(const scene::State& state);

// A transfer function as JSON: {"colors": [{"x", "rgb"}], "opacities": [{"x", "alpha"}],
// "space": "normalized" | "data", "name"} or {"preset": NAME}. "data" positions need the
// volume's value range. `where` prefixes error locations (a file name or a JSON pointer).
base::Result<scene::TransferFunction> parse_transfer_function(
        std::string_view json_text, std::optional<std::pair<double, double>> data_range,
        const std::string& where);

}  // namespace penumbra::protocol
