#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/encode/encode.hpp>
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

// How frames leave the server.
struct OutputOptions {
    // One of encode::kFrameFormats, by its name on the wire.
    encode::ImageFormat encoding = encode::kFrameFormats.front().format;
    int jpeg_quality = encode::kDefaultFrameJpegQuality;
};

// `output.jpeg_quality`'s range, which the parser holds a patch to.
inline constexpr scene::SettingRange kJpegQualityRange{
        "output/jpeg_quality", encode::kMinJpegQuality, encode::kMaxJpegQuality, true};

// The ranges hello.ranges announces and the schema generator writes into common.schema.json:
// scene::kSettingRanges' rows, then the output's.
inline constexpr auto kAnnouncedRanges = [] {
    std::array<const scene::SettingRange*, scene::kSettingRanges.size() + 1> all{};
    std::copy(scene::kSettingRanges.begin(), scene::kSettingRanges.end(), all.begin());
    all.back() = &kJpegQualityRange;
    return all;
}();

// Everything a `set` can change.
struct SessionState {
    scene::FrameRequest frame;
    OutputOptions output;
    // > 0: the server picks mode, slices, light-buffer resolution and sample distance so that a
    // frame fits this many milliseconds (from the measured accuracy table); 0: as set.
    double frame_budget_ms = 0.0;
    // Progressive stills: how many refinement steps follow a still frame of a jittered ray-cast
    // mode; 0 turns refinement off.
    int refinement_steps = scene::kDefaultRefinementSteps;
};

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

// Applies a patch onto `state`, field by field. Unknown fields, wrong types, non-finite numbers
// and values outside the limits are errors naming the JSON pointer of the field; on error `state`
// is unchanged.
base::Status apply_patch(const Patch& patch, SessionState& state, const Limits& limits);

// parse_patch, then apply_patch.
base::Status apply_patch(std::string_view patch_json, SessionState& state, const Limits& limits);

// The state in the shapes `set` accepts.
std::string state_to_json(const SessionState& state);

// A transfer function as JSON: {"colors": [{"x", "rgb"}], "opacities": [{"x", "alpha"}],
// "space": "normalized" | "data", "name"} or {"preset": NAME}. "data" positions need the
// volume's value range. `where` prefixes error locations (a file name or a JSON pointer).
base::Result<scene::TransferFunction> parse_transfer_function(
        std::string_view json_text, std::optional<std::pair<double, double>> data_range,
        const std::string& where);

}  // namespace penumbra::protocol
