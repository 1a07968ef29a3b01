#include "light_buffer.hpp"

#include "frame_target.hpp"

#include <penumbra/gpu/commands.hpp>
#include <penumbra/optics/labels.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <span>

namespace penumbra::render {

LightBufferInputs light_buffer_inputs(const scene::FrameRequest& request,
                                      const optics::Region& region, std::uint64_t volume_generation,
                                      const std::vector<glm::vec4>& table, int slab_samples,
                                      std::uint64_t labels_generation) {
    LightBufferInputs inputs{volume_generation, {}, 0, {}, request, {}};
    if (request.labels.shown()) {
        inputs.labels_generation = labels_generation;
        inputs.label_opacities = optics::bake_label_styles(request.labels).opacity_scales();
    }
    inputs.opacities.reserve(table.size());
    for (const glm::vec4& entry : table) {
        inputs.opacities.push_back(entry.a);
    }
    const scene::FrameRequest defaults;
    scene::FrameRequest& r = inputs.request;
    // The camera and the image, and how the ray caster shades and reads the buffer.
    r.camera = defaults.camera;
    r.transfer_function = {};  // in `opacities`, as the builders see it
    scene::RenderSettings& s = r.settings;
    const scene::RenderSettings& d = defaults.settings;
    s.width = d.width;
    s.height = d.height;
    s.mode = d.mode;  // every light-buffer mode fills the same buffer
    s.stage = d.stage;
    s.sample_distance = d.sample_distance;
    s.early_termination = d.early_termination;
    s.background = d.background;
    s.shading = d.shading;
    s.phong = d.phong;
    s.jitter = d.jitter;
    r.refinement = defaults.refinement;
    r.tile = defaults.tile;
    r.labels = defaults.labels;  // in `label_opacities`, as the builders see them
    // What the light meets of the cut is the region's half-spaces it clips by: none where the cut
    // tissue still casts shadows, none for a face or plane that is off or cuts nothing (a plane
    // moved while off, a crop at the volume's bounds rebuild nothing).
    r.cut = defaults.cut;
    const auto light_cut =
            std::span(region.half_spaces)
                    .first(static_cast<std::size_t>(region.count_for(optics::RegionUser::light)));
    inputs.light_cut.assign(light_cut.begin(), light_cut.end());
    s.scattering = d.scattering;
    s.light_buffer.lookup = d.light_buffer.lookup;
    // "One per voxel" and the count it resolves to fill the same buffer.
    s.light_buffer.slab_samples = slab_samples;
    // The buffer holds the fraction of the light that arrives, not its colour or strength; a
    // directional light is only its direction, a point light only its position.
    scene::Light& l = r.light;
    l.color = defaults.light.color;
    l.intensity = defaults.light.intensity;
    l.ambient = defaults.light.ambient;
    if (l.type == scene::LightType::directional) {
        l.direction = glm::normalize(l.direction);
        l.position = defaults.light.position;
    } else {
        l.direction = defaults.light.direction;
    }
    return inputs;
}

LightBuffer::LightBuffer(int slices, int resolution)
    : layers_(gpu::create_texture_array(GL_R16F, resolution, resolution, slices))
    , slices_(slices)
    , resolution_(resolution) {
    gpu::set_sampling(layers_, GL_LINEAR, GL_CLAMP_TO_EDGE);
}

std::vector<float> LightBuffer::read() const {
    std::vector<float> values(static_cast<std::size_t>(resolution_) * resolution_ * slices_);
    gpu::read_texture(layers_, GL_RED, GL_FLOAT, std::as_writable_bytes(std::span(values)));
    return values;
}

base::ImageRgba8 LightBuffer::layer_image(int layer) const {
    std::vector<float> values(static_cast<std::size_t>(resolution_) * resolution_);
    gpu::read_texture_layer(layers_, layer, resolution_, resolution_, GL_RED, GL_FLOAT,
                            std::as_writable_bytes(std::span(values)));
    return transmittance_image(values, resolution_);
}

LightBufferBuilder::LightBufferBuilder(ProgramCache& programs)
    : programs_(programs) {}

base::Status LightBufferBuilder::build(LightBuffer& target, scene::LightBufferBuilder builder,
                                       const SliceMesh& mesh, const gpu::Defines& defines,
                                       int slab_samples, gpu::GpuTimer& timer, WorkChunks& chunks) {
    const bool per_slice = builder == scene::LightBufferBuilder::per_slice;
    auto built = per_slice ? programs_.graphics("light_buffer_slice.vert",
                                                "light_buffer_slice.frag", defines)
                           : programs_.compute("light_buffer.comp", defines);
    if (!built) {
        return built.error();
    }
    const double texel_work = std::max(1, slab_samples);
    const double layer_texels = double(target.resolution()) * target.resolution();
    timer.begin();
    base::Status status =
            per_slice ? build_per_slice(target, mesh, **built, layer_texels * texel_work, chunks)
                      : build_multi_slice(target, **built, target.slices() * texel_work, chunks);
    timer.end();
    return status;
}

// Builder B in tiles of texels, each dispatch marching its texels through every slice.
base::Status LightBufferBuilder::build_multi_slice(LightBuffer& target, const gpu::Program& program,
                                                   double work_per_texel, WorkChunks& chunks) {
    gpu::clear(target.texture(), {1.0f, 1.0f, 1.0f, 1.0f});
    gpu::bind_image(0, target.texture(), GL_WRITE_ONLY, GL_R16F);
    const int resolution = target.resolution();
    const Tile tile = tile_of(chunks.work_per_chunk() / work_per_texel, resolution, resolution);
    const gpu::Groups groups = gpu::groups_covering(group_side, tile.width, tile.height);
    for (int y = 0; y < resolution; y += tile.height) {
        for (int x = 0; x < resolution; x += tile.width) {
            gpu::set_uniform(program, 0, x, y);
            gpu::dispatch(program, groups, GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            if (!chunks.continue_after_chunk()) {
                return cancelled_error();
            }
        }
    }
    gpu::memory_barrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    return base::Ok{};
}

// The paper's builder: the framebuffer holds the transmittance so far; each slice is blended in
// multiplicatively and the result copied into the next layer. Cut into groups of slices.
base::Status LightBufferBuilder::build_per_slice(LightBuffer& target, const SliceMesh& mesh,
                                                 const gpu::Program& program, double work_per_slice,
                                                 WorkChunks& chunks) {
    const int resolution = target.resolution();
    if (!scratch_ || scratch_resolution_ != resolution) {
        scratch_ = gpu::create_texture_2d(GL_R16F, resolution, resolution);
        scratch_framebuffer_ = gpu::create_framebuffer(scratch_);
        scratch_resolution_ = resolution;
    }
    if (!gpu::is_complete(scratch_framebuffer_)) {
        return base::make_error(base::ErrorCode::gl_error,
                                "the light-buffer framebuffer is incomplete", "light_buffer");
    }
    const int slices_per_chunk = static_cast<int>(
            std::clamp(chunks.work_per_chunk() / work_per_slice, 1.0, double(target.slices())));
    gpu::clear(scratch_framebuffer_, {1.0f, 1.0f, 1.0f, 1.0f});
    gpu::draw_into(scratch_framebuffer_, resolution, resolution, gpu::Blend::multiply);
    base::Status status = base::Ok{};
    for (int k = 0; k < target.slices(); ++k) {
        gpu::copy_into_layer(scratch_, target.texture(), k, resolution, resolution);
        if (k + 1 < target.slices()) {
            mesh.draw(program, k);
        }
        if ((k + 1) % slices_per_chunk == 0 && k + 1 < target.slices() &&
            !chunks.continue_after_chunk()) {
            status = cancelled_error();
            break;
        }
    }
    gpu::end_drawing();
    return status;
}

}  // namespace penumbra::render
