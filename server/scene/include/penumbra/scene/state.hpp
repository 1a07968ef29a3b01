#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/scene/enum_names.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <array>
#include <span>

namespace penumbra::scene {

// The formats a session's frames are written in, by the name the protocol, hello and the frame
// header give them; the first is a new session's.
enum class FrameFormat { jpeg, png };

inline constexpr std::array<EnumName<FrameFormat>, 2> kFrameFormatNames{{
        {FrameFormat::jpeg, "jpeg"},
        {FrameFormat::png, "png"},
}};
static_assert(names_each_value(kFrameFormatNames));

constexpr std::span<const EnumName<FrameFormat>> names_of(FrameFormat) {
    return kFrameFormatNames;
}

// The JPEG quality frames are written at until a client asks for another.
inline constexpr int kDefaultFrameJpegQuality = 85;

// How a session's frames leave the server.
struct Output {
    FrameFormat format = FrameFormat::jpeg;
    int jpeg_quality = kDefaultFrameJpegQuality;

    bool operator==(const Output&) const = default;
};

// Everything a session holds that a client can set: what each frame draws, how frames are sent,
// and how the session picks its frames' quality. The one state type: the protocol reads and
// writes it as JSON, the session keeps it, every viewer is sent it.
struct State {
    FrameRequest frame;
    Output output;
    // > 0: the server picks mode, slices, light-buffer resolution and sample distance so that a
    // frame fits this many milliseconds (from the measured accuracy table); 0: as set.
    double frame_budget_ms = 0.0;
    // Progressive stills: how many refinement steps follow a still frame of a jittered ray-cast
    // mode; 0 turns refinement off.
    int refinement_steps = kDefaultRefinementSteps;

    bool operator==(const State&) const = default;
};

// Checks every setting of the state against its row (setting_table.hpp) and `limits`, and the
// frame as validate(FrameRequest) does. Errors name the setting's path with dots
// ("light_buffer.slices", "camera.eye", "output.jpeg_quality").
base::Status validate(const State& state, const Limits& limits = {});

}  // namespace penumbra::scene
