#include "transfer_function_texture.hpp"

#include "pass_clock.hpp"

#include <penumbra/gpu/commands.hpp>
#include <penumbra/scene/transfer_function.hpp>

namespace penumbra::render {

std::optional<double> TransferFunctionTexture::update(const std::vector<glm::vec4>& table) {
    if (texture_ && table == table_) {
        return std::nullopt;
    }
    const auto start = Clock::now();
    if (!texture_) {
        texture_ = gpu::create_texture_1d(GL_RGBA32F, scene::default_table_size);
        gpu::set_sampling(texture_, GL_LINEAR, GL_CLAMP_TO_EDGE);
    }
    gpu::upload_1d(texture_, scene::default_table_size, GL_RGBA, GL_FLOAT, table.data());
    table_ = table;
    ++version_;
    return milliseconds_since(start);
}

}  // namespace penumbra::render
