#include "penumbra/render/renderer.hpp"

#include "admission.hpp"
#include "device_profile.hpp"
#include "frame_geometry.hpp"
#include "frame_planner.hpp"
#include "frame_target.hpp"
#include "half_angle_slicer.hpp"
#include "kept_stills.hpp"
#include "label_texture.hpp"
#include "light_buffer.hpp"
#include "light_buffer_cache.hpp"
#include "pass_clock.hpp"
#include "preintegration_table.hpp"
#include "program_cache.hpp"
#include "raycast_pass.hpp"
#include "settings_block.hpp"
#include "slice_geometry.hpp"
#include "transfer_function_texture.hpp"
#include "uniforms.hpp"
#include "volume_entry.hpp"
#include "work_chunks.hpp"

#include <penumbra/base/log.hpp>
#include <penumbra/base/lru_cache.hpp>
#include <penumbra/gpu/commands.hpp>
#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/readback.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/gpu/timer.hpp>

#include <algorithm>
#include <optional>
#include <utility>

namespace penumbra::render {

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

struct Renderer::Impl {
    gpu::Context context;
    RendererInfo info;
    gpu::ShaderLibrary shaders;
    ProgramCache programs;
    FrameBlocks blocks;
    FrameTarget target;
    RaycastPass raycast;
    HalfAngleSlicer half_angle;
    SliceMesh slices;
    FrameCeilings ceilings;
    double chunk_work = 0.0;
    int brick_voxels = default_brick_voxels;
    bool gradient_texture = false;  // GradientSource resolved for the device
    TransferFunctionTexture transfer_function;
    PreintegrationTable preintegration;
    LightBufferCache light_buffers;
    KeptStills stills;

    // A frame between submit() and complete(): what it needs of the GPU until then.
    struct FrameSlot {
        std::uint64_t ticket = 0;  // 0: free
        gpu::AsyncReadback readback;
        gpu::GpuTimer render_timer;
        gpu::GpuTimer light_buffer_timer;
        Frame frame;  // the report so far; complete() adds the image and the last passes
        int width = 0;
        int height = 0;
        double render_wall_ms = 0.0;     // pass_ms_since: issued, or finished without timers
        double readback_issue_ms = 0.0;  // complete() adds its wait for the fence and the copy
        std::optional<std::size_t> light_buffer_pass;  // the index of a build timed by its timer
        const char* pass_name = "raycast";
    };

    static constexpr std::size_t max_frames_in_flight = 4;
    std::vector<std::unique_ptr<FrameSlot>> slots;  // made as needed, reused
    std::uint64_t next_ticket = 0;

    // A slot for a new frame, or null when max_frames_in_flight wait for complete().
    FrameSlot* free_slot() {
        for (auto& slot : slots) {
            if (slot->ticket == 0) {
                return slot.get();
            }
        }
        if (slots.size() == max_frames_in_flight) {
            return nullptr;
        }
        return slots.emplace_back(std::make_unique<FrameSlot>()).get();
    }
    enum class LastInset { none, light_buffer, half_angle } last_inset = LastInset::none;

    // Volumes on the GPU, by the volume. The current one always stays; the light buffers of an
    // evicted one go with it.
    std::shared_ptr<const volume::Volume> volume;  // the current one
    base::LruCache<std::shared_ptr<const volume::Volume>, VolumeEntry> volumes;
    std::uint64_t next_generation = 0;
    std::vector<PassTiming> volume_passes;  // the last upload's, for the next frame's report
    // Label maps on the GPU, by the map, as the volumes: the current one (null: none) stays.
    std::shared_ptr<const volume::LabelMap> labels;
    base::LruCache<std::shared_ptr<const volume::LabelMap>, LabelTexture> label_maps;
    std::uint64_t next_labels_generation = 0;

    Impl(gpu::Context&& c, RendererInfo i, std::filesystem::path shader_dir,
         const RendererOptions& options)
        : context(std::move(c))
        , info(std::move(i))
        , shaders(std::move(shader_dir),
                  {{std::string(settings_block_file), settings_block_glsl()}})
        , programs(shaders)
        , raycast(programs)
        , half_angle(programs)
        , ceilings{options.max_frame_work, options.light_buffer_memory_budget}
        , chunk_work(options.chunk_work > 0.0 ? options.chunk_work : default_chunk_work(info))
        , brick_voxels(options.brick_voxels > 0 ? options.brick_voxels : default_brick_voxels)
        , gradient_texture(options.gradients == GradientSource::texture)
        , preintegration(info.gpu_timer_queries)
        , light_buffers(programs, options.light_buffer_memory_budget, info.gpu_timer_queries)
        , stills(options.refinement_memory_budget, info.gpu_timer_queries)
        , volumes(options.volume_memory_budget,
                  {.must_stay = [this](const auto& entry) { return entry.key == volume; },
                   .on_evict =
                           [this](const auto& entry) {
                               light_buffers.forget_volume(entry.value.generation());
                           }})
        , label_maps(options.volume_memory_budget,
                     {.must_stay = [this](const auto& entry) { return entry.key == labels; },
                      .on_evict = {}}) {}

    [[nodiscard]] scene::Limits limits() const {
        return {info.max_texture_size, info.max_array_texture_layers, info.max_texture_size};
    }

    VolumeEntry& current_volume() { return *volumes.find(volume); }

    // The current label map's texture; null without one.
    LabelTexture* current_labels() { return labels ? label_maps.find(labels) : nullptr; }

    std::uint64_t labels_generation() {
        const LabelTexture* texture = current_labels();
        return texture != nullptr ? texture->generation() : 0;
    }

    // Binds the label map with the frame's styles of its labels, and its transform from `scan`'s
    // world space.
    base::Status bind_labels(const scene::Labels& styles, const volume::Volume& scan,
                             FrameUniforms& uniforms) {
        LabelTexture* texture = current_labels();
        if (texture == nullptr) {
            return base::make_error(base::ErrorCode::invalid_frame,
                                    "the frame styles labels, but no label map is set", "labels");
        }
        if (auto status = scene::check_styles_match(styles, texture->labels().ids()); !status) {
            return status;
        }
        const optics::LabelStyleTable table = optics::bake_label_styles(styles);
        texture->bind(table);
        uniforms.world_to_label = texture->world_to_index(scan);
        uniforms.labels = glm::vec4(table.blend, 0.0f, 0.0f, 0.0f);
        return base::Ok{};
    }

    // Runs the frame's main pass (the ray caster or half-angle slicing) into the target and
    // returns how many chunks it took.
    base::Result<int> run_pass(const scene::FrameRequest& request, const FramePlan& plan,
                               const FrameGeometry& g, gpu::GpuTimer& render_timer,
                               WorkChunks& chunks) {
        const scene::RenderSettings& s = request.settings;
        if (plan.half_angle) {
            const int before = chunks.count();
            if (auto status = half_angle.run(g, s.width, s.height, s.light_buffer.resolution,
                                             plan.variant.defines(), target, render_timer, chunks);
                !status) {
                return status.error();
            }
            last_inset = LastInset::half_angle;
            return std::max(1, chunks.count() - before);
        }
        return raycast.run(plan.variant, s.width, s.height,
                           march_budget(s, g.box, g.slab_samples, info.max_shader_loop_iterations),
                           target, render_timer, chunks);
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
    RendererInfo info = describe_device(context->info());
    auto impl = std::make_unique<Impl>(
            std::move(context.value()), std::move(info),
            options.shader_dir.empty() ? gpu::default_shader_dir() : options.shader_dir, options);
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
    return impl_->light_buffers.builds();
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
    if (impl.volumes.find(volume) != nullptr) {
        impl.volume = std::move(volume);
        return base::Ok{};
    }
    auto entry = VolumeEntry::upload(volume, ++impl.next_generation, impl.info.max_3d_texture_size,
                                     impl.brick_voxels);
    if (!entry) {
        return entry.error();
    }
    impl.volume_passes = entry->upload_passes();
    impl.volume = volume;  // the volume that must stay from now on; the previous one may go
    const std::size_t bytes = entry->bytes();
    impl.volumes.insert(std::move(volume), std::move(entry.value()), bytes);
    return base::Ok{};
}

base::Status Renderer::set_labels(std::shared_ptr<const volume::LabelMap> labels) {
    Impl& impl = *impl_;
    if (!labels || labels == impl.labels) {
        impl.labels = std::move(labels);
        return base::Ok{};
    }
    if (impl.volume) {
        if (auto status = volume::check_overlap(*impl.volume, labels->indices); !status) {
            return status;
        }
    }
    if (impl.label_maps.find(labels) != nullptr) {
        impl.labels = std::move(labels);
        return base::Ok{};
    }
    auto texture = LabelTexture::upload(labels, ++impl.next_labels_generation,
                                        impl.info.max_3d_texture_size);
    if (!texture) {
        return texture.error();
    }
    impl.labels = labels;  // the map that must stay from now on; the previous one may go
    const std::size_t bytes = texture->bytes();
    impl.label_maps.insert(std::move(labels), std::move(texture.value()), bytes);
    return base::Ok{};
}

scene::Labels label_styles(const volume::LabelMap& labels) {
    scene::Labels styles;
    for (const volume::Label& label : labels.labels) {
        styles.styles.push_back({.id = label.id,
                                 .color = glm::dvec3(label.color) / 255.0,
                                 .opacity = label.opacity,
                                 .visible = label.visible});
    }
    return styles;
}

std::size_t Renderer::gpu_bytes_held() const {
    const Impl& impl = *impl_;
    return impl.volumes.bytes() + impl.light_buffers.bytes() + impl.stills.bytes() +
           impl.label_maps.bytes();
}

base::Result<Frame> Renderer::render(const scene::FrameRequest& request,
                                     const CancelPredicate& cancelled) {
    auto submitted = submit(request, cancelled);
    if (!submitted) {
        return submitted.error();
    }
    return complete(std::move(submitted.value()));
}

base::Result<SubmittedFrame> Renderer::submit(const scene::FrameRequest& request,
                                              const CancelPredicate& cancelled) {
    Impl& impl = *impl_;
    if (!impl.volume) {
        return base::make_error(base::ErrorCode::no_volume, "no volume has been set", "volume");
    }
    if (auto status = scene::validate(request, impl.limits()); !status) {
        return status.error();
    }
    FramePlan plan = plan_frame(request);
    plan.variant.gradient_texture = impl.gradient_texture && plan.variant.phong &&
                                    plan.variant.reconstruction == scene::Reconstruction::trilinear;
    VolumeEntry& volume = impl.current_volume();
    const volume::Volume& voxels = volume.volume();
    auto geometry = frame_geometry(request, plan, voxels);
    if (!geometry) {
        return geometry.error();
    }
    const FrameGeometry& g = *geometry;
    const std::vector<glm::vec4> table =
            scene::bake(request.transfer_function, scene::default_table_size,
                        {voxels.range.min, voxels.range.max, voxels.hounsfield});
    LabelVisibility labels_shown;
    if (LabelTexture* labels = impl.current_labels();
        labels != nullptr && plan.variant.labels && request.settings.empty_space_skipping) {
        labels_shown = labels->visibility(request.labels, voxels, volume.generation(),
                                          volume.empty_space().grid());
    }
    if (auto status =
                admit(request, plan, g,
                      work_context(request, volume.empty_space(), table, g.region, labels_shown),
                      impl.ceilings);
        !status) {
        return status.error();
    }
    if (auto status =
                impl.stills.check_step(request, volume.generation(), impl.labels_generation());
        !status) {
        return status.error();
    }
    WorkChunks chunks(impl.chunk_work, cancelled);
    if (chunks.cancelled()) {
        return cancelled_error();
    }
    Impl::FrameSlot* slot = impl.free_slot();
    if (slot == nullptr) {
        return base::make_error(base::ErrorCode::internal_error,
                                "more frames were submitted than the renderer holds in flight (" +
                                        std::to_string(Impl::max_frames_in_flight) + ")",
                                "render");
    }

    Frame& frame = slot->frame;
    frame = {};
    slot->light_buffer_pass.reset();
    std::vector<PassTiming>& passes = frame.report.passes;
    passes = std::exchange(impl.volume_passes, {});
    if (auto tf_ms = impl.transfer_function.update(table)) {
        passes.push_back({"transfer_function", 0.0, *tf_ms});
    }
    FrameUniforms uniforms = frame_uniforms(request, g, voxels.dims, volume.texture().value_map);
    if (plan.variant.labels) {
        if (auto status = impl.bind_labels(request.labels, voxels, uniforms); !status) {
            return status.error();
        }
    }
    impl.blocks.bind(uniforms, request);
    gpu::bind_texture(0, volume.texture().texture);
    gpu::bind_texture(1, impl.transfer_function.texture());
    if (plan.variant.preintegration) {
        auto built = impl.preintegration.update(impl.programs, impl.transfer_function.version(),
                                                plan.variant.extinction);
        if (!built) {
            return built.error();
        }
        if (*built) {
            passes.push_back({"preintegration", 0.0, **built});
        }
        gpu::bind_texture(6, impl.preintegration.texture());
    }
    if (plan.variant.empty_space_skipping) {
        if (auto status =
                    volume.bind_occupancy(impl.programs, impl.transfer_function.version(),
                                          plan.variant.labels ? impl.current_labels() : nullptr,
                                          impl.info.gpu_timer_queries, frame.report);
            !status) {
            return status.error();
        }
    }
    if (plan.variant.gradient_texture) {
        if (auto status = volume.bind_gradients(impl.programs, frame.report); !status) {
            return status.error();
        }
        impl.volumes.resize(impl.volume, volume.bytes());
    }
    if (plan.needs_light_buffer) {
        if (auto status = impl.light_buffers.use(
                    light_buffer_inputs(request, g.region, volume.generation(), table,
                                        g.slab_samples, impl.labels_generation()),
                    request.settings.light_buffer, g, plan.variant.light_buffer_defines(),
                    impl.slices, slot->light_buffer_timer, chunks, frame.report);
            !status) {
            return status.error();
        }
        if (frame.report.light_buffer == LightBufferState::built) {
            slot->light_buffer_pass = passes.size() - 1;
        }
        impl.last_inset = Impl::LastInset::light_buffer;
    }

    const auto render_start = Clock::now();
    auto pass_chunks = impl.run_pass(request, plan, g, slot->render_timer, chunks);
    if (!pass_chunks) {
        return pass_chunks.error();
    }
    // Where wall times are the only measure, finishing here splits render from readback.
    slot->render_wall_ms = pass_ms_since(render_start, impl.info.gpu_timer_queries);
    if (request.refinement.keep || request.refinement.step > 0) {
        if (auto status =
                    impl.stills.accumulate(impl.programs, request, volume.generation(),
                                           impl.labels_generation(), impl.target, frame.report);
            !status) {
            return status.error();
        }
    }
    const auto readback_start = Clock::now();
    slot->width = request.settings.width;
    slot->height = request.settings.height;
    slot->readback.start(impl.target.texture(), GL_RGBA, GL_UNSIGNED_BYTE,
                         std::size_t{4} * slot->width * slot->height);
    slot->readback_issue_ms = milliseconds_since(readback_start);
    slot->pass_name = plan.half_angle ? "half_angle" : "raycast";
    frame.report.variant = plan.variant.key();
    frame.report.stage = plan.half_angle ? "slices" : scene::to_string(plan.variant.stage);
    if (*pass_chunks > 1) {
        frame.report.stage += " (" + std::to_string(*pass_chunks) + " chunks)";
    }
    if (const GLenum error = gpu::take_error(); error != GL_NO_ERROR) {
        (void)slot->readback.wait();  // the slot is free again once its copy is no longer pending
        return base::make_error(base::ErrorCode::gl_error,
                                "OpenGL reported error " + std::to_string(error), "render");
    }
    slot->ticket = ++impl.next_ticket;
    return SubmittedFrame{.ticket = slot->ticket, .rendered = std::nullopt};
}

base::Result<Frame> Renderer::complete(SubmittedFrame submitted) {
    Impl& impl = *impl_;
    if (submitted.rendered || submitted.ticket == 0) {
        return FrameRenderer::complete(std::move(submitted));
    }
    const auto found = std::ranges::find_if(
            impl.slots, [&](const auto& slot) { return slot->ticket == submitted.ticket; });
    if (found == impl.slots.end()) {
        return FrameRenderer::complete(std::move(submitted));
    }
    Impl::FrameSlot& slot = **found;
    slot.ticket = 0;
    Frame frame = std::move(slot.frame);
    const bool timers = impl.info.gpu_timer_queries;
    // Where timers work this waits for whatever of the frame the GPU has not done yet, so that
    // the frame's wall times add up to the time the render thread spent on it.
    const auto wait_start = Clock::now();
    frame.image = base::ImageRgba8(slot.width, slot.height);
    if (auto status = slot.readback.read(std::as_writable_bytes(std::span(frame.image.pixels)));
        !status) {
        return status.error();
    }
    const double readback_ms = slot.readback_issue_ms + milliseconds_since(wait_start);
    if (slot.light_buffer_pass && timers) {
        frame.report.passes.at(*slot.light_buffer_pass).gpu_ms =
                slot.light_buffer_timer.milliseconds();
    }
    frame.report.passes.push_back(
            {slot.pass_name, gpu_ms(slot.render_timer, timers), slot.render_wall_ms});
    frame.report.passes.push_back({"readback", 0.0, readback_ms});
    if (const GLenum error = gpu::take_error(); error != GL_NO_ERROR) {
        return base::make_error(base::ErrorCode::gl_error,
                                "OpenGL reported error " + std::to_string(error), "render");
    }
    return frame;
}

base::Result<Renderer::LightBufferContents> Renderer::read_light_buffer() const {
    const LightBuffer* buffer = impl_->light_buffers.last_used();
    if (buffer == nullptr) {
        return base::make_error(base::ErrorCode::no_light_buffer,
                                "no frame has built a light buffer yet", "light_buffer");
    }
    return LightBufferContents{buffer->slices(), buffer->resolution(), buffer->read()};
}

base::Result<base::ImageRgba8> Renderer::light_inset() const {
    switch (impl_->last_inset) {
        case Impl::LastInset::light_buffer: {
            const LightBuffer* buffer = impl_->light_buffers.last_used();
            if (buffer == nullptr) {
                break;  // evicted
            }
            return buffer->layer_image(buffer->slices() - 1);
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
    return base::make_error(base::ErrorCode::no_light_buffer,
                            "only " + modes + " frames have a light buffer to show", "light_inset");
}

}  // namespace penumbra::render
