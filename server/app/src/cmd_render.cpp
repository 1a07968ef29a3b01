#include "arguments.hpp"
#include "commands.hpp"
#include "render_options.hpp"

#include <penumbra/encode/encode.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/volume/volume.hpp>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>

namespace penumbra::app {
namespace {

int fail(const base::Error& error) {
    return report_failure("render", error);
}

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    return values.empty() ? 0.0 : values[values.size() / 2];
}

void print_render_usage() {
    std::printf(
            "usage: penumbra render [options]\n\n"
            "  --volume FILE                  .nii[.gz], .nrrd/.nhdr or "
            "name_XxYxZ_type.raw[.gz],\n"
            "                                 a DICOM file or series folder (default %s)\n"
            "  --series NUMBER|UID            the series of a DICOM folder holding several\n"
            "  --spacing X,Y,Z                override the voxel spacing\n"
            "  --max-load-mb M                memory the volume load may take (default\n"
            "                                 8192; never more than the machine has)\n"
            "  --out FILE                     .png or .jpg (default frame.png)\n"
            "  --quality Q                    JPEG quality 1..100 (default 90)\n"
            "  --repeat N                     render N times, report median times\n"
            "  --light-inset FILE             also write the last light-buffer layer (sbrc\n"
            "                                 modes) or half-angle's light buffer (.png)\n"
            "  --debug-gl                     GL debug output to the log\n"
            "  --list-modes                   print the modes' names, one a line, and exit\n%s",
            default_volume_path, frame_options_help());
}

// The volume --volume names (a DICOM folder's --series), with --spacing applied.
base::Result<std::shared_ptr<const volume::Volume>> load_for_render(const Arguments& a) {
    const std::string path = a.get("volume").value_or(default_volume_path);
    volume::LoadOptions load_options;
    auto max_load_mb = a.integer("max-load-mb", static_cast<int>(load_options.max_bytes >> 20));
    if (!max_load_mb) {
        return max_load_mb.error();
    }
    if (*max_load_mb < 1) {
        return base::make_error("invalid_argument", "must be at least 1", "--max-load-mb");
    }
    load_options.max_bytes = static_cast<std::uint64_t>(*max_load_mb) << 20;
    load_options.dicom_series = a.get("series").value_or("");
    auto loaded = volume::load_volume(path, load_options);
    if (!loaded) {
        return loaded.error();
    }
    if (a.has("spacing")) {
        auto spacing = a.vec3("spacing", {});
        if (!spacing) {
            return spacing.error();
        }
        if (spacing->x <= 0.0 || spacing->y <= 0.0 || spacing->z <= 0.0) {
            return base::make_error("invalid_argument", "spacing must be positive", "--spacing");
        }
        loaded->spacing = *spacing;
    }
    return std::make_shared<const volume::Volume>(std::move(loaded.value()));
}

struct OutputOptions {
    std::string path;
    int quality = 90;
    int repeat = 1;
};

base::Result<OutputOptions> output_options(const Arguments& a) {
    OutputOptions output;
    output.path = a.get("out").value_or("frame.png");
    if (!encode::format_for_path(output.path)) {
        return base::make_error("invalid_argument", "output must end in .png or .jpg", "--out");
    }
    auto quality = a.integer("quality", output.quality);
    if (!quality) {
        return quality.error();
    }
    auto repeat = a.integer("repeat", output.repeat);
    if (!repeat || *repeat < 1 || *repeat > 10000) {
        return base::make_error("invalid_argument", "expects 1..10000", "--repeat");
    }
    output.quality = *quality;
    output.repeat = *repeat;
    return output;
}

// Renders `repeat` times and prints each pass's median times, in the order the passes first ran.
base::Result<render::Frame> render_repeated(render::Renderer& renderer,
                                            const scene::FrameRequest& request, int repeat) {
    std::map<std::string, std::vector<double>> gpu_ms;
    std::map<std::string, std::vector<double>> wall_ms;
    std::vector<std::string> order;
    render::Frame frame;
    for (int i = 0; i < repeat; ++i) {
        auto rendered = renderer.render(request);
        if (!rendered) {
            return rendered.error();
        }
        frame = std::move(rendered.value());
        for (const auto& pass : frame.report.passes) {
            if (!gpu_ms.contains(pass.name)) {
                order.push_back(pass.name);
            }
            gpu_ms[pass.name].push_back(pass.gpu_ms);
            wall_ms[pass.name].push_back(pass.wall_ms);
        }
    }
    std::printf("mode:     %s, %dx%d, %s compositing, variant %s\n",
                scene::to_string(request.settings.mode), request.settings.width,
                request.settings.height, scene::to_string(request.settings.compositing),
                frame.report.variant.c_str());
    for (const auto& name : order) {
        const double gpu = median(gpu_ms[name]);
        const std::string gpu_text = gpu < 0.0 ? "      n/a" : std::to_string(gpu).substr(0, 9);
        std::printf("pass:     %-24s gpu %9s ms   wall %9.3f ms   (median of %zu)\n", name.c_str(),
                    gpu_text.c_str(), median(wall_ms[name]), gpu_ms[name].size());
    }
    return frame;
}

base::Status write_light_inset(render::Renderer& renderer, const std::string& path) {
    auto inset = renderer.light_inset();
    if (!inset) {
        return inset.error();
    }
    if (auto status = encode::write_image(path, *inset); !status) {
        return status;
    }
    std::printf("inset:    %s (%dx%d)\n", path.c_str(), inset->width, inset->height);
    return base::Ok{};
}

}  // namespace

int run_render(const std::vector<std::string>& args) {
    std::vector<std::string> valued = frame_option_names();
    valued.insert(valued.end(), {"volume", "series", "spacing", "out", "quality", "repeat",
                                 "light-inset", "max-load-mb"});
    std::vector<std::string> flags = frame_flag_names();
    flags.insert(flags.end(), {"help", "debug-gl", "list-modes"});
    auto parsed = Arguments::parse(args, valued, flags);
    if (!parsed) {
        std::fprintf(stderr, "penumbra render: %s (see --help)\n",
                     parsed.error().to_string().c_str());
        return 2;
    }
    if (parsed->has("help")) {
        print_render_usage();
        return 0;
    }
    if (parsed->has("list-modes")) {
        for (const scene::ModeInfo& mode : scene::modes()) {
            std::printf("%s\n", mode.name.data());
        }
        return 0;
    }
    const Arguments& a = *parsed;
    auto volume = load_for_render(a);
    if (!volume) {
        return fail(volume.error());
    }
    auto request = frame_request_from(a, **volume);
    if (!request) {
        return fail(request.error());
    }
    auto output = output_options(a);
    if (!output) {
        return fail(output.error());
    }
    auto renderer =
            render::Renderer::create({.shader_dir = {}, .debug_context = a.has("debug-gl")});
    if (!renderer) {
        return fail(renderer.error());
    }
    const render::RendererInfo& info = (*renderer)->info();
    std::printf("gl:       %s | %s | %s\n", info.renderer.c_str(), info.version.c_str(),
                info.platform.c_str());
    const volume::Volume& v = **volume;
    std::printf("volume:   %s %ux%ux%u %s, range %g..%g\n", v.name.c_str(), v.dims.x, v.dims.y,
                v.dims.z, volume::to_string(v.type), v.range.min, v.range.max);
    if (auto status = (*renderer)->set_volume(*volume); !status) {
        return fail(status.error());
    }
    auto frame = render_repeated(**renderer, *request, output->repeat);
    if (!frame) {
        return fail(frame.error());
    }
    if (auto status = encode::write_image(output->path, frame->image, output->quality); !status) {
        return fail(status.error());
    }
    std::printf("light:    buffer %s, %llu build(s) in %d frame(s)\n",
                std::string(render::to_string(frame->report.light_buffer)).c_str(),
                static_cast<unsigned long long>((*renderer)->light_buffer_builds()),
                output->repeat);
    std::printf("output:   %s (%dx%d)\n", output->path.c_str(), frame->image.width,
                frame->image.height);
    if (const auto inset_path = a.get("light-inset")) {
        if (auto status = write_light_inset(**renderer, *inset_path); !status) {
            return fail(status.error());
        }
    }
    return 0;
}

}  // namespace penumbra::app
