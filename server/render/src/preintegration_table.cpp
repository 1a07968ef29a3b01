#include "preintegration_table.hpp"

#include "pass_clock.hpp"

#include <penumbra/gpu/commands.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <glm/vec4.hpp>

namespace penumbra::render {

PreintegrationTable::PreintegrationTable(bool timer_queries, int side)
    : timer_queries_(timer_queries)
    , side_(side) {}

base::Result<std::optional<double>> PreintegrationTable::update(ProgramCache& programs,
                                                                std::uint64_t tf_version,
                                                                bool extinction) {
    if (built_version_ == tf_version && built_extinction_ == extinction) {
        return std::optional<double>();
    }
    auto program =
            programs.compute("preintegration_table.comp", {{"EXTINCTION", extinction ? "1" : "0"}});
    if (!program) {
        return program.error();
    }
    const auto start = Clock::now();
    if (!texture_) {
        texture_ = gpu::create_texture_2d(GL_RGBA32F, side_, side_);
        gpu::set_sampling(texture_, GL_LINEAR, GL_CLAMP_TO_EDGE);
        cumulative_ = gpu::create_storage_buffer(sizeof(glm::vec4) * scene::default_table_size);
    }
    const gpu::Program& build = **program;
    gpu::bind_storage_buffer(0, cumulative_);
    gpu::bind_image(0, texture_, GL_WRITE_ONLY, GL_RGBA32F);
    gpu::set_uniform(build, 0, 0);  // the cumulative integral over the TF's entries
    gpu::dispatch(build, {}, GL_SHADER_STORAGE_BARRIER_BIT);
    gpu::set_uniform(build, 0, 1);  // each (front, back) from it
    gpu::dispatch(build, gpu::groups_covering(8, side_, side_),
                  GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    built_version_ = tf_version;
    built_extinction_ = extinction;
    return std::optional<double>(pass_ms_since(start, timer_queries_));
}

}  // namespace penumbra::render
