#include "penumbra/render/renderer.hpp"

#include "empty_space.hpp"
#include "frame_planner.hpp"
#include "frame_target.hpp"
#include "gradient_texture.hpp"
#include "half_angle_slicer.hpp"
#include "light_buffer.hpp"
#include "program_cache.hpp"
#include "raycast_pass.hpp"
#include "settings_block.hpp"
#include "slice_geometry.hpp"
#include "uniforms.hpp"
#include "volume_texture.hpp"
#include "work_chunks.hpp"

#include <penumbra/base/log.hpp>
#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/gpu/timer.hpp>
#include <penumbra/optics/light_slicing.hpp>
#include <penumbra/scene/box.hpp>
#include <penumbra/scene/frame_work.hpp>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <list>
#include <optional>

namespace penumbra::render {
namespace {

using Clock = std::chrono::steady_clock;

// Work per chunk when RendererOptions leaves it to the device: a software rasteriser runs this in
// a few tens of milliseconds at its slowest (light-buffer builds), a GPU runs a thousand times
// more in a few milliseconds and would idle on smaller dispatches.
constexpr double software_chunk_work = 4e6;
constexpr double hardware_chunk_work = 4e9;

double milliseconds_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

glm::vec4 v4(glm::dvec3 v, double w = 0.0) {
    return glm::vec4(glm::dvec4(v, w));
}

// Everything a light buffer's content depends on: the volume, the opacity the builders classify
// with (the baked TF's alpha channel, so a colour change reuses the buffer), and the request with
// what the builders are known not to read reset to its default. Every other member of the request
// stays in, so a setting added later rebuilds the buffer until it is shown not to matter, rather
// than serving stale shadows.
struct LightBufferInputs {
    std::uint64_t volume_generation = 0;
    std::vector<float> opacities;
    scene::FrameRequest request;

    bool operator==(const LightBufferInputs&) const = default;
};

LightBufferInputs light_buffer_inputs(const scene::FrameRequest& request,
                                      std::uint64_t volume_generation,
                                      const std::vector<glm::vec4>& table, int slab_samples) {
    LightBufferInputs inputs{volume_generation, {}, request};
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

// Where the frame's light and slices lie: CPU work that depends only on the request and the box.
struct FrameGeometry {
    scene::Box box;
    glm::dvec3 travel{0.0};  // the light's direction of travel
    std::optional<optics::LightView> light_view;
    optics::LightSlicing light_slicing;  // with light_view
    int slab_samples = 0;                // resolved; 0 without light_view
    // Half-angle slicing: the axis the slices are perpendicular to, their range along it, and
    // whether the eye composites front to back (else the view vector was flipped).
    glm::dvec3 half_angle_axis{0.0};
    optics::LightSlicing half_angle_slicing;
    bool front_to_back = true;
};

std::string mebibytes(std::size_t bytes) {
    return std::to_string(bytes >> 20) + " MiB";
}

std::string scientific(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2g", value);
    return text;
}

// The camera's view-projection for rasterised slices, flipped vertically so that image row 0 (the
// top) lands in framebuffer row 0, like the ray caster's output.
glm::dmat4 camera_view_projection(const scene::Camera& camera, const scene::CameraFrame& frame,
                                  double aspect, const scene::Box& box) {
    double far = 0.0;
    for (const auto& corner : optics::box_corners(box)) {
        far = std::max(far, glm::length(corner - camera.eye));
    }
    const glm::dvec3 up = glm::normalize(frame.up);
    const glm::dmat4 view = glm::lookAt(camera.eye, camera.eye + frame.forward, up);
    const glm::dmat4 projection =
            glm::perspective(glm::radians(camera.fov_y_degrees), aspect, 1e-3, far + 1.0);
    return glm::scale(glm::dmat4(1.0), glm::dvec3(1.0, -1.0, 1.0)) * projection * view;
}

}  // namespace

std::optional<GradientSource> parse_gradient_source(std::string_view text) {
    if (text == "automatic") {
        return GradientSource::automatic;
    }
    if (text == "central") {
        return GradientSource::central_differences;
    }
    if (text == "texture") {
        return GradientSource::texture;
    }
    return std::nullopt;
}

std::string_view to_string(LightBufferState state) {
    switch (state) {
        case LightBufferState::none:
            return "none";
        case LightBufferState::built:
            return "built";
        case LightBufferState::reused:
            return "reused";
    }
    return "none";
}

double FrameReport::gpu_total_ms() const {
    double total = 0.0;
    for (const auto& pass : passes) {
        total += pass.gpu_ms;
    }
    return total;
}

struct Renderer::Impl {
    gpu::Context context;
    RendererInfo info;
    gpu::ShaderLibrary shaders;
    ProgramCache programs;
    gpu::Buffer uniform_buffer;
    gpu::Buffer settings_buffer;  // the generated Settings block (settings_block.hpp)
    FrameTarget target;
    RaycastPass raycast;
    LightBufferBuilder light_buffer_builder;
    HalfAngleSlicer half_angle;
    SliceMesh slices;
    gpu::GpuTimer light_timer;
    gpu::GpuTimer render_timer;
    double max_frame_work = 0.0;
    double chunk_work = 0.0;
    int brick_voxels = default_brick_voxels;
    bool gradient_texture = false;  // GradientSource resolved for the device

    // Volume textures, most recently used first; the first is the current volume.
    struct CachedVolume {
        std::shared_ptr<const volume::Volume> volume;
        VolumeTexture texture;
        EmptySpaceMap empty_space;
        gpu::Texture gradients;  // built the first time a frame shades with it
        std::uint64_t generation = 0;
        std::size_t bytes = 0;
        std::uint64_t classified_tf_version = 0;  // 0: the bricks were never classified
    };

    std::list<CachedVolume> volumes;
    std::size_t volume_memory_budget = 0;
    std::uint64_t next_generation = 0;
    std::shared_ptr<const volume::Volume> volume;  // the current one
    std::uint64_t volume_generation = 0;
    const VolumeTexture* volume_texture = nullptr;
    bool volume_uploaded_this_frame = false;
    double volume_upload_ms = 0.0;
    double brick_ranges_ms = 0.0;

    gpu::Texture tf_texture;
    std::vector<glm::vec4> tf_table;  // what tf_texture holds, to skip re-uploading it
    std::uint64_t tf_version = 0;     // counts the uploads of tf_table

    // Light buffers by what their content depends on, most recently used first, so that
    // sessions with different lights or transfer functions each keep theirs.
    struct CachedLightBuffer {
        LightBufferInputs inputs;
        LightBuffer buffer;
    };

    std::list<CachedLightBuffer> light_buffers;
    std::size_t light_buffer_memory_budget = 0;
    std::uint64_t light_buffer_builds = 0;
    // The buffer the last light-buffer frame used, for light_inset() and read_light_buffer().
    const LightBuffer* last_light_buffer = nullptr;

    [[nodiscard]] std::size_t light_buffer_bytes() const {
        std::size_t total = 0;
        for (const auto& entry : light_buffers) {
            total += entry.buffer.bytes();
        }
        return total;
    }

    // Evicts least recently used buffers until `incoming` more bytes fit the budget.
    void make_room_for_light_buffer(std::size_t incoming) {
        while (!light_buffers.empty() &&
               light_buffer_bytes() + incoming > light_buffer_memory_budget) {
            if (&light_buffers.back().buffer == last_light_buffer) {
                last_light_buffer = nullptr;
            }
            light_buffers.pop_back();
        }
    }

    enum class LastInset { none, light_buffer, half_angle } last_inset = LastInset::none;

    // Progressive stills: the float mean of each kept still frame and the refinement steps
    // averaged into it so far, by the request it renders (its refinement reset) and the volume.
    struct KeptStill {
        std::uint64_t volume_generation = 0;
        scene::FrameRequest request;
        int frames = 0;  // frames averaged into `mean`: the still and its refinement steps
        gpu::Texture mean;
        std::size_t bytes = 0;
    };

    std::list<KeptStill> kept_stills;
    std::size_t refinement_memory_budget = 0;

    [[nodiscard]] static scene::FrameRequest without_refinement(scene::FrameRequest request) {
        request.refinement = {};
        return request;
    }

    // The kept still that refinement step `request.refinement.step` continues: same volume, same
    // request, and exactly the steps before this one averaged in.
    std::list<KeptStill>::iterator find_kept_still(const scene::FrameRequest& request) {
        const scene::FrameRequest key = without_refinement(request);
        return std::find_if(kept_stills.begin(), kept_stills.end(), [&](const KeptStill& kept) {
            return kept.volume_generation == volume_generation &&
                   kept.frames == request.refinement.step && kept.request == key;
        });
    }

    // Averages the frame in the target into the kept still `kept` (a new one for a still frame),
    // leaving the mean in the target.
    base::Status accumulate(const scene::FrameRequest& request, std::list<KeptStill>::iterator kept,
                            FrameReport& report) {
        const auto start = Clock::now();
        auto program = programs.compute("accumulate.comp");
        if (!program) {
            return program.error();
        }
        const scene::RenderSettings& s = request.settings;
        if (kept == kept_stills.end()) {
            scene::FrameRequest key = without_refinement(request);
            kept_stills.remove_if([&](const KeptStill& old) {
                return old.volume_generation == volume_generation && old.request == key;
            });
            const std::size_t bytes = std::size_t{16} * s.width * s.height;
            while (!kept_stills.empty() && kept_still_bytes() + bytes > refinement_memory_budget) {
                kept_stills.pop_back();
            }
            KeptStill fresh{volume_generation, std::move(key), 0,
                            gpu::create_texture(GL_TEXTURE_2D), bytes};
            glTextureStorage2D(fresh.mean.name(), 1, GL_RGBA32F, s.width, s.height);
            kept_stills.push_front(std::move(fresh));
        } else {
            kept_stills.splice(kept_stills.begin(), kept_stills, kept);
        }
        KeptStill& mean = kept_stills.front();
        glUseProgram((*program)->name());
        glBindImageTexture(0, target.texture(), 0, GL_FALSE, 0, GL_READ_WRITE,
                           FrameTarget::image_format);
        glBindImageTexture(1, mean.mean.name(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
        glUniform1i(0, mean.frames);
        glDispatchCompute(static_cast<GLuint>((s.width + group_side - 1) / group_side),
                          static_cast<GLuint>((s.height + group_side - 1) / group_side), 1);
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        report.refinement_step = mean.frames;
        ++mean.frames;
        glFinish();
        report.passes.push_back({"accumulate", 0.0, milliseconds_since(start)});
        return base::Ok{};
    }

    [[nodiscard]] std::size_t kept_still_bytes() const {
        std::size_t total = 0;
        for (const auto& kept : kept_stills) {
            total += kept.bytes;
        }
        return total;
    }

    Impl(gpu::Context&& c, std::filesystem::path shader_dir)
        : context(std::move(c))
        , shaders(std::move(shader_dir),
                  {{std::string(settings_block_file), settings_block_glsl()}})
        , programs(shaders)
        , uniform_buffer(gpu::create_buffer())
        , settings_buffer(gpu::create_buffer())
        , raycast(programs)
        , light_buffer_builder(programs)
        , half_angle(programs) {
        glNamedBufferStorage(uniform_buffer.name(), sizeof(FrameUniforms), nullptr,
                             GL_DYNAMIC_STORAGE_BIT);
        glNamedBufferStorage(settings_buffer.name(),
                             static_cast<GLsizeiptr>(settings_block_bytes()), nullptr,
                             GL_DYNAMIC_STORAGE_BIT);
    }

    [[nodiscard]] std::size_t volume_bytes() const {
        std::size_t total = 0;
        for (const auto& v : volumes) {
            total += v.bytes;
        }
        return total;
    }

    // Evicts least recently used textures beyond the budget; the current one always stays. The
    // light buffers of an evicted volume go with it: nothing can reuse them any more.
    void evict_volumes() {
        while (volumes.size() > 1 && volume_bytes() > volume_memory_budget) {
            const std::uint64_t evicted = volumes.back().generation;
            volumes.pop_back();
            light_buffers.remove_if([&](const CachedLightBuffer& entry) {
                const bool dead = entry.inputs.volume_generation == evicted;
                if (dead && &entry.buffer == last_light_buffer) {
                    last_light_buffer = nullptr;
                }
                return dead;
            });
        }
    }

    [[nodiscard]] scene::Limits limits() const {
        return {info.max_texture_size, info.max_array_texture_layers, info.max_texture_size};
    }

    // The light's view and slicing, and half-angle slicing's axis: everything about where the
    // frame's slices lie, computed on the CPU before anything is issued.
    [[nodiscard]] base::Result<FrameGeometry> frame_geometry(const scene::FrameRequest& request,
                                                             const FramePlan& plan) const {
        const scene::RenderSettings& s = request.settings;
        FrameGeometry g;
        g.box = scene::box_for_extent(volume->extent(), volume->axes);
        g.travel = optics::light_travel_direction(request.light, g.box);
        if (plan.needs_light_view) {
            auto view = optics::make_light_view(request.light, g.box);
            if (!view) {
                return view.error();
            }
            g.light_view = *view;
            g.light_slicing = optics::make_light_slicing(g.box, g.travel, s.light_buffer.slices);
            // The voxel size as the shaders see it (float), so the CPU and GPU resolve alike.
            const glm::dvec3 voxel_size(glm::vec3(g.box.size() / glm::dvec3(volume->dims)));
            g.slab_samples = optics::resolve_slab_samples(g.light_slicing, voxel_size,
                                                          s.light_buffer.slab_samples);
        }
        if (plan.half_angle) {
            // Slice along the half vector of the view and the light; when they point apart,
            // the view vector is flipped and the eye composites back to front.
            const glm::dvec3 view = glm::normalize(request.camera.target - request.camera.eye);
            g.front_to_back = glm::dot(view, g.travel) >= 0.0;
            g.half_angle_axis = glm::normalize(g.front_to_back ? view + g.travel : g.travel - view);
            g.half_angle_slicing =
                    optics::make_light_slicing(g.box, g.half_angle_axis, s.light_buffer.slices);
        }
        return g;
    }

    // What the work estimate knows of the current volume's empty space under the frame's TF
    // table: its rays leap the bricks the table leaves transparent, and no ray of any camera
    // spends more samples in the visible ones than fit along its longest stretch through them.
    [[nodiscard]] scene::WorkContext work_context(const scene::FrameRequest& request,
                                                  const std::vector<glm::vec4>& table) const {
        if (!request.settings.empty_space_skipping) {
            return {};
        }
        const EmptySpaceMap& bricks = volumes.front().empty_space;
        return {bricks.grid(), bricks.occupied_bricks(table)};
    }

    // Refuses, before anything runs, a frame over the work ceiling or a light buffer that the
    // budget could never hold.
    [[nodiscard]] base::Status admit(const scene::FrameRequest& request, const FramePlan& plan,
                                     const FrameGeometry& g,
                                     const std::vector<glm::vec4>& table) const {
        const scene::FrameWork work =
                scene::estimate_work(request, g.box, g.slab_samples, work_context(request, table));
        if (work.total() > max_frame_work) {
            return base::make_error(
                    "too_much_work",
                    "this frame asks for about " + scientific(work.total()) +
                            " shader iterations (image pixels x the samples the longest ray "
                            "can take, where empty space is skipped those that fit in the bricks "
                            "the transfer function leaves visible plus one per brick leapt, x "
                            "the mode's cost per sample, plus light-buffer texels x the slab "
                            "samples one can take), more than this server's ceiling of " +
                            scientific(max_frame_work) +
                            " per frame; use a smaller image, a larger sample distance or "
                            "fewer slices",
                    "settings");
        }
        if (plan.needs_light_buffer) {
            const scene::LightBufferSettings& lb = request.settings.light_buffer;
            const std::size_t bytes = LightBuffer::bytes_for(lb.slices, lb.resolution);
            if (bytes > light_buffer_memory_budget) {
                return base::make_error(
                        "light_buffer_too_large",
                        "a light buffer of " + std::to_string(lb.slices) + " slices of " +
                                std::to_string(lb.resolution) + "^2 texels needs " +
                                mebibytes(bytes) + ", more than the " +
                                mebibytes(light_buffer_memory_budget) +
                                " this server keeps for light buffers; use fewer slices or a "
                                "lower resolution",
                        "light_buffer");
            }
        }
        return base::Ok{};
    }

    // Returns the time spent when the table changed and had to be uploaded.
    std::optional<double> update_transfer_function(const std::vector<glm::vec4>& table) {
        if (tf_texture && table == tf_table) {
            return std::nullopt;
        }
        const auto start = Clock::now();
        if (!tf_texture) {
            tf_texture = gpu::create_texture(GL_TEXTURE_1D);
            glTextureStorage1D(tf_texture.name(), 1, GL_RGBA32F, scene::default_table_size);
            glTextureParameteri(tf_texture.name(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
            glTextureParameteri(tf_texture.name(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
            glTextureParameteri(tf_texture.name(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        }
        glTextureSubImage1D(tf_texture.name(), 0, 0, scene::default_table_size, GL_RGBA, GL_FLOAT,
                            table.data());
        tf_table = table;
        ++tf_version;
        return milliseconds_since(start);
    }

    [[nodiscard]] FrameUniforms uniforms_for(const scene::FrameRequest& request,
                                             const FrameGeometry& g) const {
        const scene::RenderSettings& s = request.settings;
        const scene::Box& box = g.box;
        const double aspect = static_cast<double>(s.width) / s.height;
        const scene::CameraFrame camera = scene::camera_frame(request.camera, aspect);
        const scene::Light& light = request.light;
        FrameUniforms u{};
        u.eye = v4(camera.eye);
        u.camera_forward = v4(camera.forward);
        u.camera_right = v4(camera.right);
        u.camera_up = v4(camera.up);
        u.box_min = v4(box.min);
        u.box_max = v4(box.max);
        u.voxel_size = v4(box.size() / glm::dvec3(volume->dims));
        u.box_to_world = glm::mat4(glm::mat3(box.axes));
        u.world_to_box = glm::mat4(glm::mat3(box.inverse_axes));
        u.background = v4(s.background, 1.0);
        u.light_radiance = v4(light.color * light.intensity);
        u.light_vector =
                v4(light.type == scene::LightType::point ? light.position
                                                         : glm::normalize(light.direction));
        u.value_map = glm::vec4(volume_texture->value_map, 0.0f, 0.0f);
        u.image_size = glm::ivec4(s.width, s.height, 0, 0);
        // What the shaders need beyond the request's own settings (the Settings block): the
        // device-bound resolution, the slab samples resolved, the cone's tangent in double.
        u.light_buffer_info = glm::vec4(static_cast<float>(s.light_buffer.resolution),
                                        static_cast<float>(g.slab_samples), 0.0f, 0.0f);
        u.cone = glm::vec4(
                static_cast<float>(std::tan(glm::radians(s.scattering.cone_angle_degrees))), 0.0f,
                0.0f, 0.0f);
        u.camera_view_projection =
                glm::mat4(camera_view_projection(request.camera, camera, aspect, box));
        if (g.light_view) {
            u.light_view_projection = glm::mat4(g.light_view->view_projection);
            u.light_inverse_view_projection = glm::mat4(g.light_view->inverse_view_projection);
            u.light_travel = v4(g.travel, g.light_view->perspective ? 1.0 : 0.0);
            const optics::LightSlicing& slicing = g.light_slicing;
            u.light_slicing = glm::vec4(
                    static_cast<float>(slicing.min), static_cast<float>(slicing.max),
                    static_cast<float>(slicing.count), static_cast<float>(slicing.spacing()));
        }
        if (g.half_angle_axis != glm::dvec3(0.0)) {
            u.half_angle_axis = v4(g.half_angle_axis, g.half_angle_slicing.spacing());
            u.half_angle_range =
                    glm::vec4(static_cast<float>(g.half_angle_slicing.min), 0.0f, 0.0f, 0.0f);
        }
        u.jitter = glm::vec4(s.jitter ? 1.0f : 0.0f, static_cast<float>(request.refinement.step),
                             0.0f, 0.0f);
        return u;
    }

    // Binds the cached light buffer the request's inputs define, building it (in chunks) when
    // none is cached. The budget keeps the total under it: older buffers are evicted first.
    base::Status use_light_buffer(const scene::FrameRequest& request, const FramePlan& plan,
                                  const FrameGeometry& g, const std::vector<glm::vec4>& table,
                                  WorkChunks& chunks, FrameReport& report) {
        const scene::LightBufferSettings& lb = request.settings.light_buffer;
        LightBufferInputs inputs =
                light_buffer_inputs(request, volume_generation, table, g.slab_samples);
        auto cached = std::find_if(light_buffers.begin(), light_buffers.end(),
                                   [&](const CachedLightBuffer& e) { return e.inputs == inputs; });
        if (cached != light_buffers.end()) {
            light_buffers.splice(light_buffers.begin(), light_buffers, cached);
            report.light_buffer = LightBufferState::reused;
        } else {
            const auto start = Clock::now();
            if (lb.builder == scene::LightBufferBuilder::per_slice) {
                slices.upload(make_slice_geometry(
                        g.box, g.travel, static_cast<float>(g.light_slicing.min),
                        static_cast<float>(g.light_slicing.max), lb.slices));
            }
            make_room_for_light_buffer(LightBuffer::bytes_for(lb.slices, lb.resolution));
            LightBuffer buffer(lb.slices, lb.resolution);
            if (glGetError() == GL_OUT_OF_MEMORY) {
                return base::make_error("gpu_out_of_memory",
                                        "not enough GPU memory for a light buffer of " +
                                                std::to_string(lb.slices) + " x " +
                                                std::to_string(lb.resolution) + "^2",
                                        "light_buffer.resolution");
            }
            if (auto status = light_buffer_builder.build(
                        buffer, lb.builder, slices,
                        {{"EXTINCTION", plan.variant.extinction ? "1" : "0"},
                         {"EMPTY_SPACE_SKIPPING", plan.variant.empty_space_skipping ? "1" : "0"}},
                        g.slab_samples, light_timer, chunks);
                !status) {
                return status;  // a cancelled build leaves a partial buffer: it is not kept
            }
            glFinish();
            report.passes.push_back({std::string("light_buffer_") + scene::to_string(lb.builder),
                                     gpu_ms(light_timer), milliseconds_since(start)});
            light_buffers.push_front({std::move(inputs), std::move(buffer)});
            ++light_buffer_builds;
            report.light_buffer = LightBufferState::built;
        }
        last_light_buffer = &light_buffers.front().buffer;
        glBindTextureUnit(2, last_light_buffer->texture());
        last_inset = LastInset::light_buffer;
        return base::Ok{};
    }

    // The ray caster's loop budget: the longest ray's samples and each sample's inner loops.
    [[nodiscard]] MarchBudget march_budget(const scene::RenderSettings& s,
                                           const FrameGeometry& g) const {
        MarchBudget budget;
        budget.max_samples_per_ray = scene::samples_per_ray(s, g.box);
        budget.iterations_per_sample =
                scene::iterations_per_sample(s, budget.max_samples_per_ray, g.slab_samples);
        budget.loop_cap = info.max_shader_loop_iterations;
        return budget;
    }

    // Runs the frame's main pass (the ray caster or half-angle slicing) into the target and
    // returns how many chunks it took.
    base::Result<int> run_pass(const scene::FrameRequest& request, const FramePlan& plan,
                               const FrameGeometry& g, WorkChunks& chunks) {
        const scene::RenderSettings& s = request.settings;
        if (plan.half_angle) {
            const int before = chunks.count();
            if (auto status = half_angle.run(slices, g.front_to_back, s.width, s.height,
                                             s.light_buffer.resolution, plan.variant.defines(),
                                             target, render_timer, chunks);
                !status) {
                return status.error();
            }
            last_inset = LastInset::half_angle;
            return std::max(1, chunks.count() - before);
        }
        return raycast.run(plan.variant, s.width, s.height, march_budget(s, g), target,
                           render_timer, chunks);
    }

    [[nodiscard]] double gpu_ms(const gpu::GpuTimer& timer) const {
        return info.gpu_timer_queries ? timer.milliseconds() : -1.0;
    }

    // The frame's uniforms and the request's settings, bound for every pass that follows.
    void upload(const FrameUniforms& u, const scene::FrameRequest& request) const {
        glNamedBufferSubData(uniform_buffer.name(), 0, sizeof(FrameUniforms), &u);
        glBindBufferBase(GL_UNIFORM_BUFFER, 0, uniform_buffer.name());
        const std::vector<std::byte> settings = settings_block_data(request);
        glNamedBufferSubData(settings_buffer.name(), 0, static_cast<GLsizeiptr>(settings.size()),
                             settings.data());
        glBindBufferBase(GL_UNIFORM_BUFFER, settings_block_binding, settings_buffer.name());
    }
};

Renderer::Renderer(std::unique_ptr<Impl> impl)
    : impl_(std::move(impl)) {}

Renderer::~Renderer() = default;

base::Result<std::unique_ptr<Renderer>> Renderer::create(const RendererOptions& options) {
    auto context = gpu::Context::create({options.debug_context});
    if (!context) {
        return context.error();
    }
    const gpu::ContextInfo& ci = context->info();
    RendererInfo info{ci.platform,
                      ci.vendor,
                      ci.renderer,
                      ci.version,
                      ci.max_3d_texture_size,
                      ci.max_texture_size,
                      ci.max_array_texture_layers};
    std::filesystem::path shader_dir =
            options.shader_dir.empty() ? gpu::default_shader_dir() : options.shader_dir;
    auto impl = std::make_unique<Impl>(std::move(context.value()), std::move(shader_dir));
    info.software = info.renderer.find("llvmpipe") != std::string::npos ||
                    info.renderer.find("softpipe") != std::string::npos;
    info.gpu_timer_queries = !info.software;
    info.max_shader_loop_iterations = info.software ? 65535 : 0;
    impl->info = std::move(info);
    impl->volume_memory_budget = options.volume_memory_budget;
    impl->light_buffer_memory_budget = options.light_buffer_memory_budget;
    impl->max_frame_work = options.max_frame_work;
    impl->gradient_texture = options.gradients == GradientSource::texture;
    impl->brick_voxels = options.brick_voxels > 0 ? options.brick_voxels : default_brick_voxels;
    impl->refinement_memory_budget = options.refinement_memory_budget;
    impl->chunk_work = options.chunk_work > 0.0 ? options.chunk_work
                       : impl->info.software    ? software_chunk_work
                                                : hardware_chunk_work;
    base::log_info("render", "OpenGL " + impl->info.version + " on " + impl->info.renderer +
                                     " via " + impl->info.platform);
    if (impl->info.software) {
        base::log_warning("render", "no GPU found: rendering on the CPU with " +
                                            impl->info.renderer + " (software rasteriser)");
    }
    return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

const RendererInfo& Renderer::info() const {
    return impl_->info;
}

std::uint64_t Renderer::light_buffer_builds() const {
    return impl_->light_buffer_builds;
}

base::Status Renderer::set_volume(std::shared_ptr<const volume::Volume> volume) {
    PENUMBRA_ASSERT(volume != nullptr, "set_volume needs a volume");
    Impl& impl = *impl_;
    if (volume == impl.volume) {
        return base::Ok{};
    }
    if (auto axes = scene::check_axes(volume->axes); !axes) {
        return axes.error();
    }
    auto cached = std::find_if(impl.volumes.begin(), impl.volumes.end(),
                               [&](const Impl::CachedVolume& v) { return v.volume == volume; });
    if (cached == impl.volumes.end()) {
        const auto start = Clock::now();
        auto texture = upload_volume(*volume, impl.info.max_3d_texture_size);
        if (!texture) {
            return texture.error();
        }
        glFinish();
        impl.volume_upload_ms = milliseconds_since(start);
        impl.volume_uploaded_this_frame = true;
        const auto bricks_start = Clock::now();
        EmptySpaceMap empty_space(compute_brick_ranges(*volume, impl.brick_voxels));
        glFinish();
        impl.brick_ranges_ms = milliseconds_since(bricks_start);
        const std::size_t bytes = volume->data.size();
        impl.volumes.push_front({volume, std::move(texture.value()), std::move(empty_space),
                                 gpu::Texture{}, ++impl.next_generation, bytes});
    } else {
        impl.volumes.splice(impl.volumes.begin(), impl.volumes, cached);
    }
    impl.evict_volumes();
    impl.volume = impl.volumes.front().volume;
    impl.volume_texture = &impl.volumes.front().texture;
    impl.volume_generation = impl.volumes.front().generation;
    return base::Ok{};
}

std::size_t Renderer::gpu_bytes_held() const {
    const Impl& impl = *impl_;
    return impl.volume_bytes() + impl.light_buffer_bytes() + impl.kept_still_bytes();
}

base::Result<Frame> Renderer::render(const scene::FrameRequest& request,
                                     const CancelPredicate& cancelled) {
    Impl& impl = *impl_;
    if (!impl.volume) {
        return base::make_error("no_volume", "no volume has been set", "volume");
    }
    if (auto status = scene::validate(request, impl.limits()); !status) {
        return status.error();
    }
    FramePlan plan = plan_frame(request);
    plan.variant.gradient_texture = impl.gradient_texture && plan.variant.phong;
    auto geometry = impl.frame_geometry(request, plan);
    if (!geometry) {
        return geometry.error();
    }
    const FrameGeometry& g = *geometry;
    const std::vector<glm::vec4> table =
            scene::bake(request.transfer_function, scene::default_table_size,
                        {impl.volume->range.min, impl.volume->range.max, impl.volume->hounsfield});
    if (auto status = impl.admit(request, plan, g, table); !status) {
        return status.error();
    }
    auto kept = impl.kept_stills.end();
    if (request.refinement.step > 0) {
        kept = impl.find_kept_still(request);
        if (kept == impl.kept_stills.end()) {
            return base::make_error("refinement_lost",
                                    "refinement step " + std::to_string(request.refinement.step) +
                                            " continues a still frame that is no longer held "
                                            "(evicted, or never kept)",
                                    "refinement.step");
        }
    }
    WorkChunks chunks(impl.chunk_work, cancelled);
    if (chunks.cancelled()) {
        return cancelled_error();
    }

    Frame frame;
    if (impl.volume_uploaded_this_frame) {
        frame.report.passes.push_back({"upload_volume", 0.0, impl.volume_upload_ms});
        frame.report.passes.push_back({"brick_ranges", 0.0, impl.brick_ranges_ms});
        impl.volume_uploaded_this_frame = false;
    }
    if (auto tf_ms = impl.update_transfer_function(table)) {
        frame.report.passes.push_back({"transfer_function", 0.0, *tf_ms});
    }
    impl.upload(impl.uniforms_for(request, g), request);
    double slice_geometry_ms = 0.0;  // CPU work of the slicing passes, counted in their time
    if (plan.half_angle) {
        const auto geometry_start = Clock::now();
        impl.slices.upload(make_slice_geometry(g.box, g.half_angle_axis, g.half_angle_slicing.min,
                                               g.half_angle_slicing.max,
                                               g.half_angle_slicing.count));
        slice_geometry_ms = milliseconds_since(geometry_start);
    }
    glBindTextureUnit(0, impl.volume_texture->texture.name());
    glBindTextureUnit(1, impl.tf_texture.name());
    if (plan.variant.empty_space_skipping) {
        Impl::CachedVolume& current = impl.volumes.front();
        if (current.classified_tf_version != impl.tf_version) {
            const auto classify_start = Clock::now();
            if (auto status = current.empty_space.classify(impl.programs); !status) {
                return status.error();
            }
            glFinish();
            current.classified_tf_version = impl.tf_version;
            frame.report.passes.push_back(
                    {"classify_bricks", 0.0, milliseconds_since(classify_start)});
        }
        glBindTextureUnit(3, current.empty_space.occupancy());
    }
    if (plan.variant.gradient_texture) {
        Impl::CachedVolume& current = impl.volumes.front();
        if (!current.gradients) {
            const auto gradients_start = Clock::now();
            auto gradients =
                    build_gradient_texture(impl.programs, current.texture, current.volume->dims);
            if (!gradients) {
                return gradients.error();
            }
            glFinish();
            current.gradients = std::move(gradients.value());
            current.bytes += gradient_texture_bytes(current.volume->dims);
            frame.report.passes.push_back(
                    {"build_gradients", 0.0, milliseconds_since(gradients_start)});
            impl.evict_volumes();
        }
        glBindTextureUnit(5, current.gradients.name());
        glBindTextureUnit(0, impl.volume_texture->texture.name());
    }
    if (plan.needs_light_buffer) {
        if (auto status = impl.use_light_buffer(request, plan, g, table, chunks, frame.report);
            !status) {
            return status.error();
        }
    }

    const auto render_start = Clock::now();
    auto pass_chunks = impl.run_pass(request, plan, g, chunks);
    if (!pass_chunks) {
        return pass_chunks.error();
    }
    glFinish();  // the frame is read back next anyway; finishing here splits render from readback
    const double render_wall_ms = milliseconds_since(render_start) + slice_geometry_ms;
    if (request.refinement.keep || request.refinement.step > 0) {
        if (auto status = impl.accumulate(request, kept, frame.report); !status) {
            return status.error();
        }
    }
    const auto readback_start = Clock::now();
    impl.target.read_back(frame.image);
    const double readback_ms = milliseconds_since(readback_start);
    frame.report.passes.push_back({plan.half_angle ? "half_angle" : "raycast",
                                   impl.gpu_ms(impl.render_timer), render_wall_ms});
    frame.report.passes.push_back({"readback", 0.0, readback_ms});
    frame.report.variant = plan.variant.key();
    frame.report.stage = plan.half_angle ? "slices" : scene::to_string(plan.variant.stage);
    if (*pass_chunks > 1) {
        frame.report.stage += " (" + std::to_string(*pass_chunks) + " chunks)";
    }
    if (const GLenum error = glGetError(); error != GL_NO_ERROR) {
        return base::make_error("gl_error", "OpenGL reported error " + std::to_string(error),
                                "render");
    }
    return frame;
}

base::Result<Renderer::LightBufferContents> Renderer::read_light_buffer() const {
    if (impl_->last_light_buffer == nullptr) {
        return base::make_error("no_light_buffer", "no frame has built a light buffer yet",
                                "light_buffer");
    }
    const LightBuffer& buffer = *impl_->last_light_buffer;
    return LightBufferContents{buffer.slices(), buffer.resolution(), buffer.read()};
}

base::Result<base::ImageRgba8> Renderer::light_inset() const {
    switch (impl_->last_inset) {
        case Impl::LastInset::light_buffer: {
            if (impl_->last_light_buffer == nullptr) {
                break;  // evicted with its volume
            }
            const LightBuffer& buffer = *impl_->last_light_buffer;
            return buffer.layer_image(buffer.slices() - 1);
        }
        case Impl::LastInset::half_angle:
            return impl_->half_angle.light_image();
        case Impl::LastInset::none:
            break;
    }
    std::string modes;
    for (const scene::ModeInfo& mode : scene::modes()) {
        if (scene::uses_light_view(mode.mode)) {
            modes += (modes.empty() ? "" : ", ") + std::string(mode.name);
        }
    }
    return base::make_error("no_light_buffer",
                            "only " + modes + " frames have a light buffer to show", "light_inset");
}

}  // namespace penumbra::render
