#include "penumbra/gpu/commands.hpp"

namespace penumbra::gpu {

void set_sampling(const Texture& texture, GLenum filter, GLenum wrap) {
    const GLuint name = texture.name();
    const auto f = static_cast<GLint>(filter);
    const auto w = static_cast<GLint>(wrap);
    glTextureParameteri(name, GL_TEXTURE_MIN_FILTER, f);
    glTextureParameteri(name, GL_TEXTURE_MAG_FILTER, f);
    glTextureParameteri(name, GL_TEXTURE_WRAP_S, w);
    glTextureParameteri(name, GL_TEXTURE_WRAP_T, w);
    glTextureParameteri(name, GL_TEXTURE_WRAP_R, w);
}

void upload_1d(const Texture& texture, int width, GLenum format, GLenum type, const void* pixels) {
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage1D(texture.name(), 0, 0, width, format, type, pixels);
}

void upload_3d(const Texture& texture, int width, int height, int depth, GLenum format, GLenum type,
               const void* pixels) {
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(texture.name(), 0, 0, 0, 0, width, height, depth, format, type, pixels);
}

void upload(const Buffer& buffer, std::span<const std::byte> bytes) {
    glNamedBufferSubData(buffer.name(), 0, static_cast<GLsizeiptr>(bytes.size()), bytes.data());
}

void read_texture(const Texture& texture, GLenum format, GLenum type, std::span<std::byte> out) {
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(texture.name(), 0, format, type, static_cast<GLsizei>(out.size()),
                      out.data());
}

void read_texture_layer(const Texture& texture, int layer, int width, int height, GLenum format,
                        GLenum type, std::span<std::byte> out) {
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureSubImage(texture.name(), 0, 0, 0, layer, width, height, 1, format, type,
                         static_cast<GLsizei>(out.size()), out.data());
}

void clear(const Texture& texture, std::array<float, 4> value) {
    glClearTexImage(texture.name(), 0, GL_RGBA, GL_FLOAT, value.data());
}

void copy_into_layer(const Texture& from, const Texture& to, int layer, int width, int height) {
    glCopyImageSubData(from.name(), GL_TEXTURE_2D, 0, 0, 0, 0, to.name(), GL_TEXTURE_2D_ARRAY, 0, 0,
                       0, layer, width, height, 1);
}

void bind_texture(GLuint unit, const Texture& texture) {
    glBindTextureUnit(unit, texture.name());
}

void bind_image(GLuint unit, const Texture& texture, GLenum access, GLenum format) {
    glBindImageTexture(unit, texture.name(), 0, GL_TRUE, 0, access, format);
}

void bind_uniform_buffer(GLuint binding, const Buffer& buffer) {
    glBindBufferBase(GL_UNIFORM_BUFFER, binding, buffer.name());
}

void bind_storage_buffer(GLuint binding, const Buffer& buffer) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buffer.name());
}

void set_uniform(const Program& program, GLint location, int value) {
    glProgramUniform1i(program.name(), location, value);
}

void set_uniform(const Program& program, GLint location, int x, int y) {
    glProgramUniform2i(program.name(), location, x, y);
}

void set_uniform(const Program& program, GLint location, float x, float y) {
    glProgramUniform2f(program.name(), location, x, y);
}

Groups groups_covering(int side, int x, int y, int z) {
    const auto groups = [side](int invocations) {
        return static_cast<GLuint>((invocations + side - 1) / side);
    };
    return {groups(x), groups(y), groups(z)};
}

void dispatch(const Program& program, Groups groups, GLbitfield barriers) {
    glUseProgram(program.name());
    glDispatchCompute(groups.x, groups.y, groups.z);
    glMemoryBarrier(barriers);
}

void memory_barrier(GLbitfield barriers) {
    glMemoryBarrier(barriers);
}

void draw_into(const Framebuffer& framebuffer, int width, int height, Blend blend) {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.name());
    glViewport(0, 0, width, height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    switch (blend) {
        case Blend::none:
            glDisable(GL_BLEND);
            return;
        case Blend::under:
            glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);
            break;
        case Blend::over:
            glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
            break;
        case Blend::multiply:
            glBlendFunc(GL_ZERO, GL_SRC_COLOR);
            break;
    }
    glEnable(GL_BLEND);
}

void set_scissor(int x, int y, int width, int height) {
    glEnable(GL_SCISSOR_TEST);
    glScissor(x, y, width, height);
}

void draw_triangles(const Program& program, const VertexArray& vertices, int first, int count) {
    glUseProgram(program.name());
    glBindVertexArray(vertices.name());
    glDrawArrays(GL_TRIANGLES, first, count);
}

void end_drawing() {
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void clear(const Framebuffer& framebuffer, std::array<float, 4> colour) {
    glClearNamedFramebufferfv(framebuffer.name(), GL_COLOR, 0, colour.data());
}

bool is_complete(const Framebuffer& framebuffer) {
    return glCheckNamedFramebufferStatus(framebuffer.name(), GL_FRAMEBUFFER) ==
           GL_FRAMEBUFFER_COMPLETE;
}

void attach_positions(const VertexArray& vertices, const Buffer& buffer, int components) {
    const GLuint name = vertices.name();
    glVertexArrayVertexBuffer(name, 0, buffer.name(), 0,
                              static_cast<GLsizei>(components * sizeof(float)));
    glVertexArrayAttribFormat(name, 0, components, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(name, 0, 0);
    glEnableVertexArrayAttrib(name, 0);
}

void finish() {
    glFinish();
}

GLenum take_error() {
    return glGetError();
}

}  // namespace penumbra::gpu
