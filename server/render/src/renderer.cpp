#include "penumbra/render/renderer.hpp"

#include "frame_planner.hpp"
#include "frame_target.hpp"
#include "half_angle_slicer.hpp"
#include "light_buffer.hpp"
#include "raycast_pass.hpp"
#include "slice_geometry.hpp"
#include "uniforms.hpp"
#include "volume_texture.hpp"

#include <penumbra/base/log.hpp>
#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/gpu/timer.hpp>
#include <penumbra/optics/light_slicing.hpp>
#include <penumbra/scene/box.hpp>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <list>
#include <cmath>
#include <optional>

namespace penumbra::render {
namespace {

using Clock = std::chrono::steady_clock;

double milliseconds_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

glm::vec4 v4(glm::dvec3 v, double w = 0.0) { return glm::vec4(glm::dvec4(v, w)); }

// Everything the light buffer's content depends on; a camera move changes none of it.
struct LightBufferKey {
    std::uint64_t volume_generation = 0;
    std::uint64_t tf_generation = 0;
    glm::dvec3 travel{0.0};
    glm::dvec3 position{0.0};
    bool point = false;
    int slices = 0;
    int resolution = 0;
    scene::LightBufferBuilder builder = scene::LightBufferBuilder::multi_slice;
    bool extinction = false;
    double opacity_unit_distance = 0.0;
    double compensation = 0.0;
    int slab_samples = 0;

    bool operator==(const LightBufferKey&) const = default;
};

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
    gpu::Buffer uniform_buffer;
    FrameTarget target;
    RaycastPass raycast;
    LightBufferBuilder light_buffer_builder;
    HalfAngleSlicer half_angle;
    SliceMesh slices;
    gpu::GpuTimer light_timer;
    gpu::GpuTimer render_timer;

    // Volume textures, most recently used first; the first is the current volume.
    struct CachedVolume {
        std::shared_ptr<const volume::Volume> volume;
        VolumeTexture texture;
        std::uint64_t generation = 0;
        std::size_t bytes = 0;
    };
    std::list<CachedVolume> volumes;
    std::size_t volume_memory_budget = 0;
    std::uint64_t next_generation = 0;
    std::shared_ptr<const volume::Volume> volume;  // the current one
    std::uint64_t volume_generation = 0;
    const VolumeTexture* volume_texture = nullptr;
    bool volume_uploaded_this_frame = false;
    double volume_upload_ms = 0.0;

    gpu::Texture tf_texture;
    std::vector<glm::vec4> tf_table;  // what tf_texture holds, to skip re-uploading it
    std::uint64_t tf_generation = 0;

    // Light buffers by what they depend on, most recently used first, so that sessions with
    // different lights or transfer functions each keep theirs; the first is the current one.
    struct CachedLightBuffer {
        LightBufferKey key;
        LightBuffer buffer;
    };
    std::list<CachedLightBuffer> light_buffers;
    std::size_t light_buffer_memory_budget = 0;
    std::uint64_t light_buffer_builds = 0;

    [[nodiscard]] std::size_t light_buffer_bytes() const {
        std::size_t total = 0;
        for (const auto& entry : light_buffers) {
            total += entry.buffer.bytes();
        }
        return total;
    }

    void evict_light_buffers() {
        while (light_buffers.size() > 1 && light_buffer_bytes() > light_buffer_memory_budget) {
            light_buffers.pop_back();
        }
    }
    enum class LastInset { none, light_buffer, half_angle } last_inset = LastInset::none;

    Impl(gpu::Context&& c, std::filesystem::path shader_dir)
        : context(std::move(c))
        , shaders(std::move(shader_dir))
        , uniform_buffer(gpu::create_buffer())
        , raycast(shaders)
        , light_buffer_builder(shaders)
        , half_angle(shaders) {
        glNamedBufferStorage(uniform_buffer.name(), sizeof(FrameUniforms), nullptr,
                             GL_DYNAMIC_STORAGE_BIT);
    }

    [[nodiscard]] std::size_t volume_bytes() const {
        std::size_t total = 0;
        for (const auto& v : volumes) {
            total += v.bytes;
        }
        return total;
    }

    // Evicts least recently used textures beyond the budget; the current one always stays.
    void evict_volumes() {
        while (volumes.size() > 1 && volume_bytes() > volume_memory_budget) {
            volumes.pop_back();
        }
    }

    [[nodiscard]] scene::Limits limits() const {
        return {info.max_texture_size, info.max_array_texture_layers, info.max_texture_size};
    }

    // Returns the time spent when the table changed and had to be uploaded.
    std::optional<double> update_transfer_function(const scene::TransferFunction& tf) {
        std::vector<glm::vec4> table = scene::bake(tf, scene::default_table_size);
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
        tf_table = std::move(table);
        ++tf_generation;
        return milliseconds_since(start);
    }

    FrameUniforms uniforms_for(const scene::FrameRequest& request, const scene::Box& box) const {
        const scene::RenderSettings& s = request.settings;
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
        u.background = v4(s.background, 1.0);
        u.light_radiance = v4(light.color * light.intensity, light.ambient);
        u.light_vector = v4(light.type == scene::LightType::point ? light.position
                                                                  : glm::normalize(light.direction));
        u.shading = glm::vec4(static_cast<float>(s.shading.diffuse),
                              static_cast<float>(s.shading.specular),
                              static_cast<float>(s.shading.shininess), 0.0f);
        u.value_map = glm::vec4(volume_texture->value_map, 0.0f, 0.0f);
        u.march = glm::vec4(static_cast<float>(s.sample_distance),
                            static_cast<float>(s.opacity_unit_distance),
                            static_cast<float>(s.early_termination), 0.0f);
        u.image_size = glm::ivec4(s.width, s.height, 0, 0);
        u.light_buffer_info = glm::vec4(static_cast<float>(s.light_buffer.resolution),
                                        static_cast<float>(s.light_buffer.compensation), 0.0f,
                                        0.0f);
        u.scattering = glm::vec4(static_cast<float>(s.scattering.shell_radius),
                                 static_cast<float>(s.scattering.shell_rings),
                                 static_cast<float>(s.scattering.shell_center_weight), 0.0f);
        u.cone = glm::vec4(static_cast<float>(std::tan(glm::radians(s.scattering.cone_angle_degrees))),
                           static_cast<float>(s.scattering.cone_center_weight), 0.0f, 0.0f);
        u.camera_view_projection = glm::mat4(camera_view_projection(request.camera, camera, aspect, box));
        return u;
    }

    [[nodiscard]] double gpu_ms(const gpu::GpuTimer& timer) const {
        return info.gpu_timer_queries ? timer.milliseconds() : -1.0;
    }

    void upload(const FrameUniforms& u) const {
        glNamedBufferSubData(uniform_buffer.name(), 0, sizeof(FrameUniforms), &u);
        glBindBufferBase(GL_UNIFORM_BUFFER, 0, uniform_buffer.name());
    }
};

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

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
    base::log_info("render", "OpenGL " + impl->info.version + " on " + impl->info.renderer +
                                     " via " + impl->info.platform);
    if (impl->info.software) {
        base::log_warning("render", "no GPU found: rendering on the CPU with " +
                                            impl->info.renderer + " (software rasteriser)");
    }
    return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

const RendererInfo& Renderer::info() const { return impl_->info; }

std::uint64_t Renderer::light_buffer_builds() const { return impl_->light_buffer_builds; }

base::Status Renderer::set_volume(std::shared_ptr<const volume::Volume> volume) {
    PENUMBRA_ASSERT(volume != nullptr, "set_volume needs a volume");
    Impl& impl = *impl_;
    if (volume == impl.volume) {
        return base::Ok{};
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
        const std::size_t bytes = volume->data.size();
        impl.volumes.push_front({volume, std::move(texture.value()), ++impl.next_generation, bytes});
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
    return impl.volume_bytes() + impl.light_buffer_bytes();
}

base::Result<Frame> Renderer::render(const scene::FrameRequest& request) {
    Impl& impl = *impl_;
    if (!impl.volume) {
        return base::make_error("no_volume", "no volume has been set", "volume");
    }
    if (auto status = scene::validate(request, impl.limits()); !status) {
        return status.error();
    }
    const scene::RenderSettings& s = request.settings;
    const FramePlan plan = plan_frame(request);
    const scene::Box box = scene::box_for_extent(impl.volume->extent());
    std::optional<optics::LightView> light_view;
    if (plan.needs_light_view) {
        auto view = optics::make_light_view(request.light, box);
        if (!view) {
            return view.error();
        }
        light_view = *view;
    }

    Frame frame;
    if (impl.volume_uploaded_this_frame) {
        frame.report.passes.push_back({"upload_volume", 0.0, impl.volume_upload_ms});
        impl.volume_uploaded_this_frame = false;
    }
    if (auto tf_ms = impl.update_transfer_function(request.transfer_function)) {
        frame.report.passes.push_back({"transfer_function", 0.0, *tf_ms});
    }

    FrameUniforms uniforms = impl.uniforms_for(request, box);
    const glm::dvec3 travel = optics::light_travel_direction(request.light, box);
    if (light_view) {
        uniforms.light_view_projection = glm::mat4(light_view->view_projection);
        uniforms.light_inverse_view_projection = glm::mat4(light_view->inverse_view_projection);
        uniforms.light_travel = v4(travel, light_view->perspective ? 1.0 : 0.0);
        const optics::LightSlicing slicing =
                optics::make_light_slicing(box, travel, s.light_buffer.slices);
        uniforms.light_slicing = glm::vec4(static_cast<float>(slicing.min),
                                           static_cast<float>(slicing.max),
                                           static_cast<float>(slicing.count),
                                           static_cast<float>(slicing.spacing()));
        uniforms.light_buffer_info.z = static_cast<float>(optics::resolve_slab_samples(
                slicing, glm::dvec3(uniforms.voxel_size),
                s.light_buffer.slab_samples));
    }
    bool front_to_back = true;
    double slice_geometry_ms = 0.0;  // CPU work of the slicing passes, counted in their time
    if (plan.half_angle) {
        // Slice along the half vector of the view and the light; when they point apart, the
        // view vector is flipped and the eye composites back to front.
        const glm::dvec3 view = glm::normalize(request.camera.target - request.camera.eye);
        front_to_back = glm::dot(view, travel) >= 0.0;
        const glm::dvec3 axis = glm::normalize(front_to_back ? view + travel : travel - view);
        const optics::LightSlicing along_axis =
                optics::make_light_slicing(box, axis, s.light_buffer.slices);
        uniforms.half_angle_axis = v4(axis, along_axis.spacing());
        uniforms.half_angle_range = glm::vec4(static_cast<float>(along_axis.min), 0.0f, 0.0f, 0.0f);
        const auto geometry_start = Clock::now();
        impl.slices.upload(make_slice_geometry(box, axis, along_axis.min, along_axis.max,
                                               along_axis.count));
        slice_geometry_ms = milliseconds_since(geometry_start);
    }
    impl.upload(uniforms);
    glBindTextureUnit(0, impl.volume_texture->texture.name());
    glBindTextureUnit(1, impl.tf_texture.name());
    const gpu::Defines defines = plan.variant.defines();

    if (plan.needs_light_buffer) {
        LightBufferKey key{impl.volume_generation,
                           impl.tf_generation,
                           travel,
                           request.light.position,
                           request.light.type == scene::LightType::point,
                           s.light_buffer.slices,
                           s.light_buffer.resolution,
                           s.light_buffer.builder,
                           plan.variant.extinction,
                           s.opacity_unit_distance,
                           s.light_buffer.compensation,
                           static_cast<int>(uniforms.light_buffer_info.z)};
        if (!key.point) {
            key.position = glm::dvec3(0.0);
        }
        auto cached = std::find_if(impl.light_buffers.begin(), impl.light_buffers.end(),
                                   [&](const Impl::CachedLightBuffer& e) { return e.key == key; });
        if (cached != impl.light_buffers.end()) {
            impl.light_buffers.splice(impl.light_buffers.begin(), impl.light_buffers, cached);
            frame.report.light_buffer = "reused";
        } else {
            const auto start = Clock::now();
            if (s.light_buffer.builder == scene::LightBufferBuilder::per_slice) {
                impl.slices.upload(make_slice_geometry(box, travel,
                                                       uniforms.light_slicing.x,
                                                       uniforms.light_slicing.y,
                                                       s.light_buffer.slices));
            }
            LightBuffer buffer(s.light_buffer.slices, s.light_buffer.resolution);
            if (glGetError() == GL_OUT_OF_MEMORY) {
                return base::make_error("gpu_out_of_memory",
                                        "not enough GPU memory for a light buffer of " +
                                                std::to_string(s.light_buffer.slices) + " x " +
                                                std::to_string(s.light_buffer.resolution) + "^2",
                                        "light_buffer.resolution");
            }
            if (auto status = impl.light_buffer_builder.build(
                        buffer, s.light_buffer.builder, impl.slices,
                        {{"EXTINCTION", plan.variant.extinction ? "1" : "0"}}, impl.light_timer);
                !status) {
                return status.error();
            }
            glFinish();
            frame.report.passes.push_back(
                    {std::string("light_buffer_") + scene::to_string(s.light_buffer.builder),
                     impl.gpu_ms(impl.light_timer), milliseconds_since(start)});
            impl.light_buffers.push_front({key, std::move(buffer)});
            impl.evict_light_buffers();
            ++impl.light_buffer_builds;
            frame.report.light_buffer = "built";
        }
        glBindTextureUnit(2, impl.light_buffers.front().buffer.texture());
        impl.last_inset = Impl::LastInset::light_buffer;
    }

    const auto render_start = Clock::now();
    std::string pass_name = "raycast";
    int chunks = 1;
    if (plan.half_angle) {
        pass_name = "half_angle";
        if (auto status = impl.half_angle.run(impl.slices, front_to_back, s.width, s.height,
                                              s.light_buffer.resolution, defines, impl.target,
                                              impl.render_timer);
            !status) {
            return status.error();
        }
        impl.last_inset = Impl::LastInset::half_angle;
    } else {
        // The longest ray crosses the box's diagonal; a shadow ray at most the same again.
        const double diagonal = glm::length(box.size());
        MarchBudget budget;
        budget.max_samples_per_ray =
                static_cast<int>(std::ceil(diagonal / s.sample_distance)) + 1;
        switch (plan.variant.shadows) {
            case Shadows::rays: budget.iterations_per_sample = 2 + budget.max_samples_per_ray; break;
            case Shadows::light_buffer:
                budget.iterations_per_sample =
                        plan.variant.scattering == Scattering::shell ? 4 + 2 * s.scattering.shell_rings
                        : plan.variant.scattering == Scattering::cone ? 10
                                                                       : 1;
                if (plan.variant.local_light_lookup) {
                    budget.iterations_per_sample +=
                            1 + static_cast<int>(uniforms.light_buffer_info.z);
                }
                break;
            case Shadows::none: budget.iterations_per_sample = 1; break;
        }
        budget.loop_cap = impl.info.max_shader_loop_iterations;
        auto dispatches = impl.raycast.run(plan.variant, s.width, s.height, budget, impl.target,
                                           impl.render_timer);
        if (!dispatches) {
            return dispatches.error();
        }
        chunks = *dispatches;
    }
    glFinish();  // the frame is read back next anyway; finishing here splits render from readback
    const double render_wall_ms = milliseconds_since(render_start) + slice_geometry_ms;
    const auto readback_start = Clock::now();
    impl.target.read_back(frame.image);
    const double readback_ms = milliseconds_since(readback_start);
    frame.report.passes.push_back({pass_name, impl.gpu_ms(impl.render_timer), render_wall_ms});
    frame.report.passes.push_back({"readback", 0.0, readback_ms});
    frame.report.variant = plan.variant.key();
    frame.report.stage = plan.half_angle ? "slices" : scene::to_string(plan.variant.stage);
    if (chunks > 1) {
        frame.report.stage += " (" + std::to_string(chunks) + " chunks)";
    }
    if (const GLenum error = glGetError(); error != GL_NO_ERROR) {
        return base::make_error("gl_error", "OpenGL reported error " + std::to_string(error),
                                "render");
    }
    return frame;
}

base::Result<Renderer::LightBufferContents> Renderer::read_light_buffer() const {
    if (impl_->light_buffers.empty()) {
        return base::make_error("no_light_buffer", "no frame has built a light buffer yet",
                                "light_buffer");
    }
    const LightBuffer& buffer = impl_->light_buffers.front().buffer;
    return LightBufferContents{buffer.slices(), buffer.resolution(), buffer.read()};
}

base::Result<base::ImageRgba8> Renderer::light_inset() const {
    switch (impl_->last_inset) {
        case Impl::LastInset::light_buffer: {
            const LightBuffer& buffer = impl_->light_buffers.front().buffer;
            return buffer.layer_image(buffer.slices() - 1);
        }
        case Impl::LastInset::half_angle: return impl_->half_angle.light_image();
        case Impl::LastInset::none: break;
    }
    return base::make_error("no_light_buffer",
                            "only sbrc, sbrc_shell, sbrc_cone and half_angle frames have a light "
                            "buffer to show",
                            "light_inset");
}

}  // namespace penumbra::render
