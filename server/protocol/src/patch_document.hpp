#pragma once

// What a Patch holds. Private to the protocol module.

#include "json_fields.hpp"

#include <penumbra/protocol/scene_json.hpp>

namespace penumbra::protocol {

struct Patch::Document {
    json_fields::json object;  // a JSON object, depth-limited when it was parsed
};

}  // namespace penumbra::protocol
