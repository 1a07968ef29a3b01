#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/render/frame.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/label_map.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::render {

// Where shaded samples get their gradient: central differences of six volume samples each, or
// one sample of a texture of per-voxel differences built once per volume (8 bytes a voxel more
// GPU memory). `automatic` is central differences: the texture is faster on llvmpipe (0.54-0.97
// of the time, `penumbra bench modes` prints the comparison) but its constant extrapolation at the
// box faces departs from the reference's clamped samples, so it stays a choice.
enum class GradientSource { automatic, central_differences, texture };

// "automatic", "central" or "texture" (as `penumbra bench modes --gradients` takes them).
std::optional<GradientSource> parse_gradient_source(std::string_view text);

struct RendererOptions {
    std::filesystem::path shader_dir;  // empty: the default search (gpu::default_shader_dir)
    bool debug_context = false;        // GL debug output routed to the log
    // Volume textures stay on the GPU, least recently used evicted first, while they fit this.
    std::size_t volume_memory_budget = std::size_t{2} << 30;
    // Light buffers stay cached by what their content depends on (the volume, the TF's opacity
    // and the request less what the builders do not read: light_buffer_inputs in light_buffer.hpp),
    // least recently used evicted first so that together they never exceed this; a single buffer
    // larger than it is refused.
    std::size_t light_buffer_memory_budget = std::size_t{1} << 30;
    // The most work one frame may ask for, in shader inner-loop iterations
    // (scene::estimate_work: an upper bound for any camera and light; with empty-space skipping,
    // per ray the samples that fit along the longest line through the bricks the frame's TF
    // leaves visible, plus one per brick leapt); larger requests are refused with
    // `too_much_work` before anything runs. No ceiling by default: the CLI renders what it is
    // asked; `serve` sets its own.
    double max_frame_work = std::numeric_limits<double>::infinity();
    // Frames are issued in chunks of about this much work (tiles of the image, ranges of steps
    // along the rays, tiles or groups of slices of the light buffer), between which the renderer
    // waits for the GPU and asks whether the frame was cancelled. 0: sized for the device (a
    // fraction of a second per chunk on a software rasteriser).
    double chunk_work = 0.0;
    // Voxels per side of the bricks that empty-space skipping leaps over; 0: the renderer's
    // default (chosen by measurement, see `penumbra bench modes --brick-voxels`).
    int brick_voxels = 0;
    GradientSource gradients = GradientSource::automatic;
    // Progressive stills: the float mean of each kept still frame (16 bytes a pixel) stays on the
    // GPU, least recently used evicted first, while they fit this; a refinement step whose mean
    // was evicted fails with `refinement_lost`.
    std::size_t refinement_memory_budget = std::size_t{256} << 20;
};

// Asked on the render thread between chunks of a frame; returning true abandons the frame, which
// then fails with the error code `cancelled`. Must be cheap and safe to call from that thread
// while others change what it reads (atomics).
using CancelPredicate = std::function<bool()>;

// What the renderer runs on, for logs, CLI output and the protocol's hello.
struct RendererInfo {
    std::string platform;
    std::string vendor;
    std::string renderer;
    std::string version;
    int max_3d_texture_size = 0;
    int max_texture_size = 0;
    int max_array_texture_layers = 0;
    // Mesa's software rasterisers (llvmpipe, softpipe): no GPU found, frames are drawn on the CPU.
    bool software = false;
    // False on Mesa's software rasterisers, whose timer queries do not measure compute dispatches
    // and return garbage for draws; pass times then carry gpu_ms = -1 and only wall times count.
    bool gpu_timer_queries = true;
    // Mesa's llvmpipe stops a shader invocation after 65535 loop iterations in all (its
    // LP_MAX_TGSI_LOOP_ITERATIONS); the compute ray caster then marches long rays in several
    // dispatches. 0 = no such limit.
    int max_shader_loop_iterations = 0;
    // How many frames a scheduler keeps submitted (FrameRenderer::submit) before it waits for the
    // oldest: 2 on a GPU, so that the CPU issues the next frame while the GPU draws this one; 1
    // on a software rasteriser, which draws as the frame is issued, so that a second frame in
    // flight would only hold back the first.
    int frames_in_flight = 1;
};

// A frame whose GPU work has been issued (FrameRenderer::submit) and that complete() waits for.
// Every submitted frame must be completed, in the order it was submitted.
struct SubmittedFrame {
    std::uint64_t ticket = 0;  // the renderer's name for the frame in flight
    // The frame itself, for a renderer that renders it whole in submit().
    std::optional<Frame> rendered;
};

// What the scheduler renders through, so that scheduling can be tested with a fake.
class FrameRenderer {
public:
    virtual ~FrameRenderer() = default;

    [[nodiscard]] virtual const RendererInfo& info() const = 0;

    virtual base::Status set_volume(std::shared_ptr<const volume::Volume> volume) = 0;

    // The label map frames that style labels draw inside the volume (Renderer::set_labels); a
    // renderer that draws none refuses one. By value: an override keeps the map.
    // NOLINTNEXTLINE(performance-unnecessary-value-param)
    virtual base::Status set_labels(std::shared_ptr<const volume::LabelMap> labels) {
        if (!labels) {
            return base::Ok{};
        }
        return base::make_error(base::ErrorCode::unsupported_settings,
                                "this renderer draws no label maps", "labels");
    }

    // Renders one frame, or fails with `too_much_work` (over the work ceiling) or
    // `light_buffer_too_large` (over the light-buffer budget), both before anything runs,
    // `refinement_lost` (a refinement step whose earlier steps are no longer held),
    // `cancelled` (when `cancelled` said so between chunks), or why it could not. Without a
    // predicate the frame cannot be cancelled and runs in as few dispatches as the GL allows.
    virtual base::Result<Frame> render(const scene::FrameRequest& request,
                                       const CancelPredicate& cancelled) = 0;

    base::Result<Frame> render(const scene::FrameRequest& request) { return render(request, {}); }

    // Issues the frame's work and its readback without waiting for the GPU, failing as render()
    // does (`cancelled` is asked between chunks, as there); at most
    // RendererInfo::frames_in_flight frames (and never more than four) wait for complete() at a
    // time. A renderer that does not pipeline renders the frame whole here.
    virtual base::Result<SubmittedFrame> submit(const scene::FrameRequest& request,
                                                const CancelPredicate& cancelled) {
        auto frame = render(request, cancelled);
        if (!frame) {
            return frame.error();
        }
        return SubmittedFrame{.ticket = 0, .rendered = std::move(frame.value())};
    }

    // Waits for a submitted frame and returns it, its pass times complete.
    virtual base::Result<Frame> complete(SubmittedFrame submitted) {
        if (!submitted.rendered) {
            return base::make_error(base::ErrorCode::internal_error,
                                    "this renderer has no such frame in flight", "render");
        }
        return std::move(*submitted.rendered);
    }

    // Bytes of GPU memory held by cached volume textures and light buffers.
    [[nodiscard]] virtual std::size_t gpu_bytes_held() const = 0;
};

// The styles of a label map's labels as its files give them: each label's colour, opacity and
// visibility (shown and opaque as the scan where the files say nothing).
[[nodiscard]] scene::Labels label_styles(const volume::LabelMap& labels);

// The GPU renderer. It owns the headless GL context, so it is created, used and destroyed on one
// thread. GPU objects are cached by what they depend on: volume textures (several, LRU under a
// memory budget), the TF table until the TF changes, light buffers by what they hold (several,
// LRU under their budget), compiled shader variants for the renderer's life.
class Renderer final : public FrameRenderer {
public:
    static base::Result<std::unique_ptr<Renderer>> create(const RendererOptions& options = {});

    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;
    ~Renderer();

    [[nodiscard]] const RendererInfo& info() const override;

    // Makes the volume current, uploading it unless its texture is still cached, without losing
    // 16-bit/float precision.
    base::Status set_volume(std::shared_ptr<const volume::Volume> volume) override;

    // Sets the label map frames draw inside the volume when their request styles its labels
    // (scene::Labels, one style per label of the map: label_styles gives its defaults); null
    // draws none. Label maps stay on the GPU, least recently used evicted first, under the volume
    // budget, so that sessions drawing different maps switch between them at no cost. The map keeps
    // its own grid and transform; it must overlap the current volume (no_overlap) and be only
    // rotated or reflected (unsupported_orientation).
    base::Status set_labels(std::shared_ptr<const volume::LabelMap> labels) override;

    // Renders one frame of the current volume in any mode of DESIGN.md §1: complete(submit()).
    using FrameRenderer::render;
    base::Result<Frame> render(const scene::FrameRequest& request,
                               const CancelPredicate& cancelled) override;

    // The frame's passes, then its readback into a pixel-pack buffer of its own and a fence; where
    // timer queries time the GPU, nothing waits for the GPU on the way.
    base::Result<SubmittedFrame> submit(const scene::FrameRequest& request,
                                        const CancelPredicate& cancelled) override;

    // Waits for the frame's fence, reads its pixels and its passes' timers.
    base::Result<Frame> complete(SubmittedFrame submitted) override;

    [[nodiscard]] std::size_t gpu_bytes_held() const override;

    // How many times the light attenuation buffer was built since the renderer was created.
    [[nodiscard]] std::uint64_t light_buffer_builds() const;

    struct LightBufferContents {
        int slices = 0;
        int resolution = 0;
        std::vector<float> values;  // layer after layer, R x R each, rows bottom-up
    };

    // The light buffer the last light-buffer frame used (for tests and tools).
    base::Result<LightBufferContents> read_light_buffer() const;

    // The paper's inset image: the last light-buffer layer after an sbrc frame, or the final
    // light buffer after a half_angle frame.
    base::Result<base::ImageRgba8> light_inset() const;

private:
    struct Impl;
    explicit Renderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::render
