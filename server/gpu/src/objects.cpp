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

}  // namespace penumbra::gpu
