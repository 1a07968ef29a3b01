#include "half_angle_slicer.hpp"

#include <algorithm>
#include <vector>

namespace penumbra::render {

HalfAngleSlicer::HalfAngleSlicer(ProgramCache& programs)
    : programs_(programs) {}

void HalfAngleSlicer::ensure_buffers(int width, int height, int light_resolution) {
    if (!eye_ || width != width_ || height != height_) {
        eye_ = gpu::create_texture(GL_TEXTURE_2D);
        // Float so that hundreds of blended slices do not band.
        glTextureStorage2D(eye_.name(), 1, GL_RGBA32F, width, height);
        eye_framebuffer_ = gpu::create_framebuffer();
        glNamedFramebufferTexture(eye_framebuffer_.name(), GL_COLOR_ATTACHMENT0, eye_.name(), 0);
        width_ = width;
        height_ = height;
    }
    if (!light_ || light_resolution != light_resolution_) {
        light_ = gpu::create_texture(GL_TEXTURE_2D);
        glTextureStorage2D(light_.name(), 1, GL_R16F, light_resolution, light_resolution);
        glTextureParameteri(light_.name(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(light_.name(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(light_.name(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(light_.name(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        light_framebuffer_ = gpu::create_framebuffer();
        glNamedFramebufferTexture(light_framebuffer_.name(), GL_COLOR_ATTACHMENT0, light_.name(),
                                  0);
        light_resolution_ = light_resolution;
    }
}

base::Status HalfAngleSlicer::run(const SliceMesh& mesh, bool front_to_back, int width, int height,
                                  int light_resolution, const gpu::Defines& defines,
                                  FrameTarget& target, gpu::GpuTimer& timer, WorkChunks& chunks) {
    const auto pass_program = [&](bool light_pass) {
        gpu::Defines all = defines;
        all.emplace_back("HALF_ANGLE_LIGHT_PASS", light_pass ? "1" : "0");
        return programs_.graphics("half_angle.vert", "half_angle.frag", all);
    };
    auto eye_program = pass_program(false);
    auto light_program = pass_program(true);
    auto resolve_program = programs_.compute("resolve.comp");
    if (!eye_program || !light_program || !resolve_program) {
        return !eye_program     ? eye_program.error()
               : !light_program ? light_program.error()
                                : resolve_program.error();
    }
    ensure_buffers(width, height, light_resolution);
    target.ensure(width, height);

    timer.begin();
    const float clear_eye[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const float clear_light[4] = {1.0f, 1.0f, 1.0f, 1.0f};
    glClearNamedFramebufferfv(eye_framebuffer_.name(), GL_COLOR, 0, clear_eye);
    glClearNamedFramebufferfv(light_framebuffer_.name(), GL_COLOR, 0, clear_light);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBindTextureUnit(3, light_.name());
    mesh.bind();
    const double work_per_slice =
            double(width) * height + double(light_resolution) * light_resolution;
    const int slices_per_chunk = static_cast<int>(
            std::clamp(chunks.work_per_chunk() / work_per_slice, 1.0, double(mesh.slices())));
    base::Status status = base::Ok{};
    for (int k = 0; k < mesh.slices(); ++k) {
        glBindFramebuffer(GL_FRAMEBUFFER, eye_framebuffer_.name());
        glViewport(0, 0, width, height);
        if (front_to_back) {
            glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);  // "under"
        } else {
            glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // "over"
        }
        glUseProgram((*eye_program)->name());
        mesh.draw(k);

        glBindFramebuffer(GL_FRAMEBUFFER, light_framebuffer_.name());
        glViewport(0, 0, light_resolution, light_resolution);
        glBlendFunc(GL_ZERO, GL_SRC_COLOR);
        glUseProgram((*light_program)->name());
        mesh.draw(k);
        if ((k + 1) % slices_per_chunk == 0 && k + 1 < mesh.slices() &&
            !chunks.continue_after_chunk()) {
            status = cancelled_error();
            break;
        }
    }
    glDisable(GL_BLEND);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!status) {
        timer.end();
        return status;
    }

    glUseProgram((*resolve_program)->name());
    glBindTextureUnit(0, eye_.name());
    glBindImageTexture(0, target.texture(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                       FrameTarget::image_format);
    glDispatchCompute(static_cast<GLuint>((width + 7) / 8), static_cast<GLuint>((height + 7) / 8),
                      1);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    timer.end();
    return base::Ok{};
}

base::ImageRgba8 HalfAngleSlicer::light_image() const {
    std::vector<float> values(static_cast<std::size_t>(light_resolution_) * light_resolution_);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(light_.name(), 0, GL_RED, GL_FLOAT,
                      static_cast<GLsizei>(values.size() * sizeof(float)), values.data());
    return transmittance_image(values, light_resolution_);
}

}  // namespace penumbra::render
