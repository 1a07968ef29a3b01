#include "penumbra/gpu/objects.hpp"

namespace penumbra::gpu {

Texture create_texture(GLenum target) {
    GLuint name = 0;
    glCreateTextures(target, 1, &name);
    return Texture(name);
}

Buffer create_buffer() {
    GLuint name = 0;
    glCreateBuffers(1, &name);
    return Buffer(name);
}

Framebuffer create_framebuffer() {
    GLuint name = 0;
    glCreateFramebuffers(1, &name);
    return Framebuffer(name);
}

VertexArray create_vertex_array() {
    GLuint name = 0;
    glCreateVertexArrays(1, &name);
    return VertexArray(name);
}

Query create_query(GLenum target) {
    GLuint name = 0;
    glCreateQueries(target, 1, &name);
    return Query(name);
}

Texture create_texture_1d(GLenum format, int width) {
    Texture texture = create_texture(GL_TEXTURE_1D);
    glTextureStorage1D(texture.name(), 1, format, width);
    return texture;
}

Texture create_texture_2d(GLenum format, int width, int height) {
    Texture texture = create_texture(GL_TEXTURE_2D);
    glTextureStorage2D(texture.name(), 1, format, width, height);
    return texture;
}

Texture create_texture_3d(GLenum format, int width, int height, int depth) {
    Texture texture = create_texture(GL_TEXTURE_3D);
    glTextureStorage3D(texture.name(), 1, format, width, height, depth);
    return texture;
}

Texture create_texture_array(GLenum format, int width, int height, int layers) {
    Texture texture = create_texture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(texture.name(), 1, format, width, height, layers);
    return texture;
}

Buffer create_storage_buffer(std::size_t bytes) {
    Buffer buffer = create_buffer();
    glNamedBufferStorage(buffer.name(), static_cast<GLsizeiptr>(bytes), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    return buffer;
}

Framebuffer create_framebuffer(const Texture& colour) {
    Framebuffer framebuffer = create_framebuffer();
    glNamedFramebufferTexture(framebuffer.name(), GL_COLOR_ATTACHMENT0, colour.name(), 0);
    return framebuffer;
}

}  // namespace penumbra::gpu
