#include "label_texture.hpp"

#include <penumbra/gpu/commands.hpp>
#include <penumbra/scene/box.hpp>

#include <span>
#include <string>

namespace penumbra::render {

LabelTexture::LabelTexture(std::shared_ptr<const volume::LabelMap> labels, std::uint64_t generation,
                           gpu::Texture indices)
    : labels_(std::move(labels))
    , generation_(generation)
    , indices_(std::move(indices)) {}

base::Result<LabelTexture> LabelTexture::upload(std::shared_ptr<const volume::LabelMap> labels,
                                                std::uint64_t generation, int max_3d_texture_size) {
    const volume::Volume& indices = labels->indices;
    const glm::uvec3 dims = indices.dims;
    const auto limit = static_cast<unsigned>(max_3d_texture_size);
    if (dims.x > limit || dims.y > limit || dims.z > limit) {
        return base::make_error(base::ErrorCode::volume_too_large,
                                "the label map exceeds this GPU's 3D texture limit of " +
                                        std::to_string(max_3d_texture_size) + " per side",
                                indices.name);
    }
    if (auto axes = scene::check_axes(indices.axes); !axes) {
        return axes.error();
    }
    const bool narrow = indices.type == volume::VoxelType::uint8;
    PENUMBRA_ASSERT(narrow || indices.type == volume::VoxelType::uint16,
                    "label indices are 8 or 16 bits");
    const glm::ivec3 size(dims);
    gpu::Texture texture =
            gpu::create_texture_3d(narrow ? GL_R8UI : GL_R16UI, size.x, size.y, size.z);
    gpu::upload_3d(texture, size.x, size.y, size.z, GL_RED_INTEGER,
                   narrow ? GL_UNSIGNED_BYTE : GL_UNSIGNED_SHORT, indices.data.data());
    gpu::set_sampling(texture, GL_NEAREST, GL_CLAMP_TO_EDGE);
    if (gpu::take_error() == GL_OUT_OF_MEMORY) {
        return base::make_error(base::ErrorCode::gpu_out_of_memory,
                                "not enough GPU memory for the label map", indices.name);
    }
    return LabelTexture(std::move(labels), generation, std::move(texture));
}

glm::mat4 LabelTexture::world_to_index(const volume::Volume& scan) const {
    const volume::Volume& indices = labels_->indices;
    return glm::mat4(optics::world_to_label_index(
            scene::patient_placement(scan.origin, scan.axes, scan.spacing, glm::dvec3(scan.dims)),
            indices.origin, indices.axes, indices.spacing));
}

void LabelTexture::bind(const optics::LabelStyleTable& styles) {
    const auto width = static_cast<int>(styles.texels.size());
    if (!styles_ || styles.texels.size() != uploaded_.size()) {
        styles_ = gpu::create_texture_1d(GL_RGBA32F, width);
        gpu::set_sampling(styles_, GL_NEAREST, GL_CLAMP_TO_EDGE);
        uploaded_.clear();
    }
    if (styles.texels != uploaded_) {
        gpu::upload_1d(styles_, width, GL_RGBA, GL_FLOAT, styles.texels.data());
        uploaded_ = styles.texels;
        ++styles_version_;
    }
    gpu::bind_texture(7, indices_);
    gpu::bind_texture(8, styles_);
}

const BrickLabels& LabelTexture::brick_labels(const volume::Volume& scan,
                                              std::uint64_t scan_generation, glm::ivec3 grid) {
    if (bricks_of_ != scan_generation || bricks_.grid != grid) {
        bricks_ = compute_brick_labels(scan, grid, *labels_);
        const auto upload = [](const std::vector<std::uint32_t>& values) {
            gpu::Buffer buffer = gpu::create_storage_buffer(sizeof(std::uint32_t) * values.size());
            gpu::upload(buffer, std::as_bytes(std::span(values)));
            return buffer;
        };
        brick_starts_ = upload(bricks_.starts);
        brick_indices_ = upload(bricks_.indices);
        bricks_of_ = scan_generation;
    }
    return bricks_;
}

void LabelTexture::bind_brick_labels() const {
    gpu::bind_storage_buffer(1, brick_starts_);
    gpu::bind_storage_buffer(2, brick_indices_);
}

LabelVisibility LabelTexture::visibility(const scene::Labels& styles, const volume::Volume& scan,
                                         std::uint64_t scan_generation, glm::ivec3 grid) {
    LabelVisibility out;
    out.bricks = &brick_labels(scan, scan_generation, grid);
    out.generation = generation_;
    for (const glm::vec4& texel : optics::bake_label_styles(styles).texels) {
        out.shown.push_back(texel.a > 0.0f);
    }
    return out;
}

}  // namespace penumbra::render
