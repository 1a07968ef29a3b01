// Builds every server->client message the protocol module can produce and writes them to
// PENUMBRA_SENT_MESSAGES (one {"kind", "message"} a line) for validate_messages.py, which checks
// them against proto/v1 (the protocol_schema_validation test).

#include "examples.hpp"

#include <penumbra/protocol/frame_header.hpp>
#include <penumbra/protocol/messages.hpp>
#include <penumbra/protocol/scene_json.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace penumbra::protocol {
namespace {

using nlohmann::json;

std::vector<std::string> text_messages() {
    std::vector<std::string> out;
    out.push_back(hello_message(
            Limits{}, {"llvmpipe (LLVM 15.0.6, 256 bits)", "4.5 (Core)", "Linux x86_64"}));
    Limits configured;
    configured.max_message_bytes = 1 << 20;
    configured.max_requests_per_second = 0.5;
    out.push_back(hello_message(configured, {"NVIDIA H100", "4.6.0 NVIDIA", "Linux"}));

    VolumeSummary colin;
    colin.id = "colin27";
    colin.name = "Colin27 T1 MRI";
    colin.dims[0] = 181;
    colin.dims[1] = 217;
    colin.dims[2] = 181;
    colin.voxel_type = "uint8";
    colin.range[1] = 254;
    colin.loaded = true;
    VolumeSummary ct;
    ct.id = "ct/head_256x256x113_uint16.raw.gz";
    ct.name = "CT head";
    ct.dims[0] = 256;
    ct.dims[1] = 256;
    ct.dims[2] = 113;
    ct.spacing[2] = 2.0;
    ct.voxel_type = "uint16";
    ct.hounsfield = true;
    VolumeSummary floats = colin;
    floats.id = "float";
    floats.voxel_type = "float32";
    floats.range[0] = -1.5;
    floats.range[1] = 1e6;
    VolumeSummary unloaded;  // as net lists a volume it has not loaded yet
    unloaded.id = "visible_human.nrrd";
    unloaded.name = unloaded.id;
    unloaded.label_map = false;
    VolumeSummary atlas = unloaded;
    atlas.id = "aal.nii.gz";
    atlas.label_map = true;
    out.push_back(volumes_message(1, {colin, ct, floats, unloaded, atlas}, Listing::complete));
    out.push_back(volumes_message(std::nullopt, {}, Listing::scanning));
    out.push_back(volumes_message(2, {colin}, Listing::cut_short));

    std::vector<scene::State> states;
    for (const auto& name : scene::preset_names()) {
        scene::State state;
        state.frame.transfer_function = scene::preset(name).value();
        states.push_back(state);
    }
    states.emplace_back();
    for (const auto& example : test::valid_examples()) {
        const auto request = parse_request(example.text, Limits{});
        if (request.ok() && std::holds_alternative<Set>(request->message)) {
            scene::State state;
            state.frame.transfer_function = scene::preset("grey_ramp").value();
            EXPECT_TRUE(apply_patch(std::get<Set>(request->message).patch, state, Limits{}).ok());
            states.push_back(state);
        }
    }
    std::vector<std::uint64_t> histogram(256, 7);
    histogram[0] = 4'000'000'000ULL;
    const std::string owner_token = "0123456789abcdef0123456789abcdef";
    for (std::size_t i = 0; i < states.size(); ++i) {
        const auto id = static_cast<std::int64_t>(i);
        const std::string session = "s" + std::to_string(i);
        out.push_back(
                i % 2 == 1 ? joined_message(id, session, colin, histogram, states[i])
                           : opened_message(id, session, colin, histogram, states[i], owner_token));
    }
    out.push_back(opened_message(std::nullopt, "s0", ct, {}, states[0], owner_token));
    for (std::size_t i = 0; i < states.size(); ++i) {
        out.push_back(state_message("s" + std::to_string(i), states[i]));
    }

    for (const char* of : {"close"}) {
        out.push_back(ack_message(5, of));
        out.push_back(ack_message(std::nullopt, of));
    }
    for (const scene::State& state : states) {
        out.push_back(set_ack_message(5, state));
    }
    out.push_back(set_ack_message(std::nullopt, states.front()));
    for (const base::ErrorCode c : kWireCodes) {
        out.push_back(error_message(-3, base::make_error(c, "something went wrong", "")));
    }
    // The errors the server sends for each invalid example, as net would build them.
    // A `set` that parses is refused when its patch is applied.
    for (const auto& example : test::invalid_examples()) {
        const auto request = parse_request(example.text, Limits{});
        if (!request.ok()) {
            out.push_back(error_message(request_id_of(example.text), request.error()));
            continue;
        }
        scene::State state;
        state.frame.transfer_function = scene::preset("grey_ramp").value();
        const auto applied = apply_patch(std::get<Set>(request->message).patch, state, Limits{});
        EXPECT_FALSE(applied.ok()) << example.name;
        if (!applied.ok()) {
            out.push_back(error_message(request->id, applied.error()));
        }
    }
    scene::State labelled;
    labelled.frame.labels.styles = {
            {.id = 1, .color = {0.8, 0.8, 0.8}},
            {.id = 45, .color = {0.2, 0.2, 0.8}, .opacity = 0.5, .visible = false}};
    const std::vector<LabelSummary> aal{{1, "Precentral_L", {204, 204, 204}, 28174},
                                        {45, "Cuneus_L", {54, 54, 203}, 14015}};
    out.push_back(labels_message(7, "s0", "aal.nii.gz", aal, labelled));
    out.push_back(labels_message(std::nullopt, "s1", "aal.nii.gz", aal, labelled));
    out.push_back(labels_message(8, "s0", "", {}, states.front()));
    PickSummary miss;
    miss.x = 0.5;
    miss.y = 1.0;
    out.push_back(picked_message(10, "s0", miss));
    PickSummary bone = miss;
    bone.x = 0.25;
    bone.y = 0.5;
    bone.hit = true;
    bone.position[0] = -12.5;
    bone.position[1] = 30.0;
    bone.position[2] = 41.25;
    bone.value = 1250.0;
    bone.hounsfield = true;
    out.push_back(picked_message(11, "s0", bone));
    out.push_back(picked_message(12, "s0",
                                 PickSummary{.x = 0.0,
                                             .y = 0.0,
                                             .hit = true,
                                             .position = {40.0, -20.0, 55.5},
                                             .value = 87.0,
                                             .label_id = 1,
                                             .label_name = "Precentral_L"}));
    ExportSummary export_started;
    export_started.export_id = "5f0c2a9e41d37b88c6e2f01a9b4d7e63";
    export_started.state = "running";
    export_started.width = 4096;
    export_started.height = 3072;
    out.push_back(export_status_message(14, export_started));
    ExportSummary exported = export_started;
    exported.state = "done";
    exported.progress = 1.0;
    exported.tiles = 6;
    exported.bytes = 9123456;
    exported.url = "/exports/5f0c2a9e41d37b88c6e2f01a9b4d7e63";
    out.push_back(export_status_message(14, exported));
    ExportSummary failed = export_started;
    failed.state = "failed";
    failed.progress = 0.25;
    failed.tiles = 4;
    failed.error = base::make_error(base::ErrorCode::too_much_work, "a tile asks too much", "size");
    out.push_back(export_status_message(std::nullopt, failed));
    ExportSummary movie = exported;
    movie.width = 1280;
    movie.height = 720;
    movie.tiles = 2;
    movie.frames = 120;
    movie.url = "/exports/0d9e8c7b6a5f4e3d2c1b0a9f8e7d6c5b";
    out.push_back(export_status_message(15, movie));
    out.push_back(state_message("s0", labelled));
    out.push_back(set_ack_message(9, labelled));
    out.push_back(stats_message(6, "{}"));
    out.push_back(stats_message(std::nullopt, R"({"sessions":2,"frames":{"sent":10}})"));
    return out;
}

std::vector<std::string> frame_headers() {
    FrameHeader h;
    h.frame = 0;
    h.request = 4;
    h.session = "s1";
    h.width = 512;
    h.height = 512;
    h.encoding = "jpeg";
    h.mode = "dvr";
    h.light_buffer = "none";
    h.quality = "full";
    std::vector<FrameHeader> headers = {h};
    h.frame = 18'446'744'073'709'551'615ULL;
    h.request = -1;
    h.encoding = "png";
    h.mode = "sbrc_shell";
    h.interactive = true;
    h.light_buffer = "built";
    h.passes = {{"light_buffer", -1.0, 2.5}, {"raycast", 4.0, 4.5}};
    h.queued_ms = 0.1;
    h.render_ms = 6.5;
    h.readback_ms = 0.4;
    h.encode_ms = 1.2;
    headers.push_back(h);
    h.light_buffer = "reused";
    h.width = 1;
    headers.push_back(h);

    std::vector<std::string> out;
    const std::vector<std::uint8_t> image = {0x89, 'P', 'N', 'G'};
    for (const auto& header : headers) {
        const auto frame = unpack_frame(pack_frame(header, image));
        EXPECT_TRUE(frame.ok());
        if (frame.ok()) {
            out.push_back(frame->header_json);
        }
    }
    return out;
}

TEST(SentMessages, EveryServerMessageIsWrittenForSchemaValidation) {
    std::string lines;
    std::size_t count = 0;
    for (const std::string& text : text_messages()) {
        ASSERT_TRUE(json::accept(text)) << text;
        lines += R"({"kind":"text","message":)" + text + "}\n";
        ++count;
    }
    for (const std::string& header : frame_headers()) {
        ASSERT_TRUE(json::accept(header)) << header;
        lines += R"({"kind":"frame_header","message":)" + header + "}\n";
        ++count;
    }
    EXPECT_GT(count, 100U);

    // Written whole and renamed, so that concurrent runs (the discovered test and the fixture)
    // never leave a partial file for the validator.
    const std::filesystem::path target(PENUMBRA_SENT_MESSAGES);
    const std::filesystem::path temporary =
            target.string() + ".tmp." + std::to_string(static_cast<long>(::getpid()));
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out << lines;
        ASSERT_TRUE(out.good()) << temporary;
    }
    std::filesystem::rename(temporary, target);
}

}  // namespace
}  // namespace penumbra::protocol
