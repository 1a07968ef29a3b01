#include "penumbra/cli/transfer_function_file.hpp"

#include <penumbra/protocol/scene_json.hpp>

#include <fstream>
#include <sstream>

namespace penumbra::cli {

base::Result<scene::TransferFunction> load_transfer_function(const std::string& preset_or_path,
                                                             const volume::ValueRange& range) {
    if (preset_or_path.size() < 5 ||
        preset_or_path.compare(preset_or_path.size() - 5, 5, ".json") != 0) {
        return scene::preset(preset_or_path);
    }
    std::ifstream in(preset_or_path);
    if (!in) {
        return base::make_error(base::ErrorCode::not_found,
                                "cannot read the transfer-function file", preset_or_path);
    }
    std::stringstream text;
    text << in.rdbuf();
    return protocol::parse_transfer_function(text.str(), std::pair{range.min, range.max},
                                             preset_or_path);
}

}  // namespace penumbra::cli
