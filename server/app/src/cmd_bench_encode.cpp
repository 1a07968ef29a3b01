// `penumbra bench encode`: the options of bench::bench_encoders, on frames of one view rendered
// at each size asked for.

#include "commands.hpp"
#include "framed_volume.hpp"
#include "sweep_lists.hpp"

#include <penumbra/bench/encode_bench.hpp>
#include <penumbra/cli/frame_options.hpp>
#include <penumbra/cli/options.hpp>
#include <penumbra/encode/encode.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/turntable.hpp>

#include <cstdio>
#include <string>
#include <vector>

namespace penumbra::app {

using namespace cli;

namespace {

int fail(const base::Error& error) {
    return report_failure("bench encode", error);
}

struct EncodeOptions {
    int quality = 85;
    int repeat = 15;
    // --stream: an orbit of the view as a stream of JPEG frames and as an H.264 stream.
    bool stream = false;
    int stream_frames = 24;
};

po::options_description encode_options(std::string& volume, EncodeOptions& o) {
    po::options_description options = option_group("options");
    options.add_options()("help", "this text")(
            "volume", po::value(&volume)->value_name("PATH")->default_value(volume), "the volume")(
            "sides", with_default<Counts>("N,...", "512,1024"),
            "square frames of these sides, rendered once each")(
            "jpeg-quality",
            whole_number(&o.quality, encode::kMinJpegQuality, encode::kMaxJpegQuality),
            "JPEG quality")("repeat", whole_number(&o.repeat, 1, 1000),
                            "encodes per encoder, format and frame (the median is shown)")(
            "stream", po::bool_switch(&o.stream),
            "instead: the view orbiting, as a stream of JPEG frames and as an H.264 stream at "
            "equal SSIM (bytes, SSIM and encode time per frame)")(
            "stream-size", po::value<ImageSize>()->value_name("WxH")->default_value({512, 512}),
            "--stream: the frames' size")(
            "orbit-steps", with_default<Numbers>("DEG,...", "1,3"),
            "--stream: degrees the view turns a frame, a sequence each")(
            "stream-frames", whole_number(&o.stream_frames, 2, 600), "--stream: frames a sequence");
    options.add(frame_options({"size"}));
    return options;
}

base::Status bench_encode(const po::variables_map& a, const std::string& path,
                          const EncodeOptions& o) {
    auto framed = framed_volume(a, path);
    if (!framed) {
        return framed.error();
    }
    std::vector<bench::EncodeFrame> frames;
    for (const int side : a["sides"].as<Counts>().values) {
        scene::FrameRequest request = framed->frame;
        request.settings.width = side;
        request.settings.height = side;
        auto rendered = framed->renderer->render(request);
        if (!rendered) {
            return rendered.error();
        }
        frames.push_back({std::string(scene::to_string(request.settings.mode)) + " " +
                                  std::to_string(side) + "x" + std::to_string(side),
                          std::move(rendered->image)});
    }
    std::printf("penumbra bench encode: %s, tf %s\n", framed->volume->name.c_str(),
                framed->frame.transfer_function.name.c_str());
    return bench::bench_encoders(frames, o.quality, o.repeat, stdout);
}

// --stream: per orbit step, the frames of the view turning by it, rendered as stills (no
// refinement: what a dragging client gets frame after frame).
base::Status bench_stream(const po::variables_map& a, const std::string& path,
                          const EncodeOptions& o) {
    auto framed = framed_volume(a, path);
    if (!framed) {
        return framed.error();
    }
    const ImageSize size = a["stream-size"].as<ImageSize>();
    std::vector<bench::StreamSequence> sequences;
    for (const double step : a["orbit-steps"].as<Numbers>().values) {
        bench::StreamSequence sequence;
        char name[96];
        std::snprintf(name, sizeof name, "%s %dx%d, %g deg a frame",
                      std::string(scene::to_string(framed->frame.settings.mode)).c_str(),
                      size.width, size.height, step);
        sequence.name = name;
        for (int k = 0; k < o.stream_frames; ++k) {
            scene::FrameRequest request = framed->frame;
            request.settings.width = size.width;
            request.settings.height = size.height;
            const scene::TurnedView view =
                    scene::turned_view(request.camera, request.light, step * k);
            request.camera = view.camera;
            request.light = view.light;
            auto rendered = framed->renderer->render(request);
            if (!rendered) {
                return rendered.error();
            }
            sequence.frames.push_back(std::move(rendered->image));
        }
        sequences.push_back(std::move(sequence));
    }
    std::printf("penumbra bench encode --stream: %s, tf %s, %d frames a sequence\n",
                framed->volume->name.c_str(), framed->frame.transfer_function.name.c_str(),
                o.stream_frames);
    return bench::bench_streams(sequences, o.quality, stdout);
}

}  // namespace

int run_bench_encode(const std::vector<std::string>& args) {
    std::string volume = default_volume_path;
    EncodeOptions encode;
    const po::options_description options = encode_options(volume, encode);
    auto parsed = parse_options(args, options);
    if (!parsed) {
        return report_usage_error("bench encode", parsed.error());
    }
    if (parsed->count("help") != 0) {
        print_help("bench encode [options]",
                   "Milliseconds and bytes per frame, JPEG and PNG: TurboJPEG and libpng (what "
                   "frames are\nencoded with) against OpenImageIO's writers (what they were "
                   "encoded with before), in\nturn on the same rendered frames.",
                   options);
        return 0;
    }
    if (auto status = encode.stream ? bench_stream(*parsed, volume, encode)
                                    : bench_encode(*parsed, volume, encode);
        !status) {
        return fail(status.error());
    }
    return 0;
}

}  // namespace penumbra::app
