#include "penumbra/render/renderer.hpp"

#include "raycast_pass.hpp"
#include "uniforms.hpp"
#include "volume_texture.hpp"

#include <penumbra/base/log.hpp>
#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/gpu/timer.hpp>
#include <penumbra/scene/box.hpp>

#include <glm/geometric.hpp>

#include <chrono>
#include <optional>

namespace penumbra::render {
namespace {

using Clock = std::chrono::steady_clock;

double milliseconds_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

glm::vec4 v4(glm::dvec3 v, double w = 0.0) { return glm::vec4(glm::dvec4(v, w)); }

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
    RaycastPass raycast;
    gpu::GpuTimer timer;

    std::shared_ptr<const volume::Volume> volume;
    std::optional<VolumeTexture> volume_texture;
    bool volume_uploaded_this_frame = false;
    double volume_upload_ms = 0.0;

    gpu::Texture tf_texture;
    std::vector<glm::vec4> tf_table;  // what tf_texture holds, to skip re-uploading it

    Impl(gpu::Context&& c, std::filesystem::path shader_dir)
        : context(std::move(c))
        , shaders(std::move(shader_dir))
        , raycast(shaders) {}

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
        return milliseconds_since(start);
    }

    FrameUniforms uniforms_for(const scene::FrameRequest& request) const {
        const scene::RenderSettings& s = request.settings;
        const double aspect = static_cast<double>(s.width) / s.height;
        const scene::CameraFrame camera = scene::camera_frame(request.camera, aspect);
        const scene::Box box = scene::box_for_extent(volume->extent());
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
        return u;
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
    impl->info = std::move(info);
    base::log_info("render", "OpenGL " + impl->info.version + " on " + impl->info.renderer +
                                     " via " + impl->info.platform);
    return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

const RendererInfo& Renderer::info() const { return impl_->info; }

base::Status Renderer::set_volume(std::shared_ptr<const volume::Volume> volume) {
    PENUMBRA_ASSERT(volume != nullptr, "set_volume needs a volume");
    if (volume == impl_->volume) {
        return base::Ok{};
    }
    const auto start = Clock::now();
    auto texture = upload_volume(*volume, impl_->info.max_3d_texture_size);
    if (!texture) {
        return texture.error();
    }
    glFinish();
    impl_->volume_upload_ms = milliseconds_since(start);
    impl_->volume_uploaded_this_frame = true;
    impl_->volume_texture = std::move(texture.value());
    impl_->volume = std::move(volume);
    return base::Ok{};
}

base::Result<Frame> Renderer::render(const scene::FrameRequest& request) {
    Impl& impl = *impl_;
    if (!impl.volume) {
        return base::make_error("no_volume", "no volume has been set", "volume");
    }
    if (auto status = scene::validate(request, impl.info.max_texture_size); !status) {
        return status.error();
    }
    const scene::Mode mode = request.settings.mode;
    if (mode != scene::Mode::dvr && mode != scene::Mode::phong) {
        return base::make_error("unsupported_mode",
                                std::string("mode '") + scene::to_string(mode) +
                                        "' is not available in this renderer yet",
                                "mode");
    }
    Frame frame;
    if (impl.volume_uploaded_this_frame) {
        frame.report.passes.push_back({"upload_volume", 0.0, impl.volume_upload_ms});
        impl.volume_uploaded_this_frame = false;
    }
    if (auto tf_ms = impl.update_transfer_function(request.transfer_function)) {
        frame.report.passes.push_back({"transfer_function", 0.0, *tf_ms});
    }

    RaycastVariant variant;
    variant.phong = mode == scene::Mode::phong;
    variant.extinction = request.settings.compositing == scene::Compositing::extinction;
    variant.point_light = variant.phong && request.light.type == scene::LightType::point;
    variant.stage = request.settings.stage;

    glBindTextureUnit(0, impl.volume_texture->texture.name());
    glBindTextureUnit(1, impl.tf_texture.name());
    const auto raycast_start = Clock::now();
    if (auto status = impl.raycast.run(variant, impl.uniforms_for(request), impl.timer); !status) {
        return status.error();
    }
    glFinish();  // the frame is read back next anyway; finishing here splits render from readback
    const double raycast_wall_ms = milliseconds_since(raycast_start);
    const auto readback_start = Clock::now();
    impl.raycast.read_back(frame.image);
    const double readback_ms = milliseconds_since(readback_start);
    frame.report.passes.push_back({"raycast", impl.timer.milliseconds(), raycast_wall_ms});
    frame.report.passes.push_back({"readback", 0.0, readback_ms});
    frame.report.variant = variant.key();
    frame.report.stage = scene::to_string(variant.stage);
    if (const GLenum error = glGetError(); error != GL_NO_ERROR) {
        return base::make_error("gl_error", "OpenGL reported error " + std::to_string(error),
                                "render");
    }
    return frame;
}

}  // namespace penumbra::render
