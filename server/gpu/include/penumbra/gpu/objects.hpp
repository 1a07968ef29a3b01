#pragma once

#include <epoxy/gl.h>

#include <cstddef>
#include <utility>

namespace penumbra::gpu {

// A move-only owner of one GL object name. A default-constructed owner holds no object (name 0);
// release() gives the name up without deleting it.
template <class Traits>
class Object {
public:
    Object() = default;

    explicit Object(GLuint name)
        : name_(name) {}

    Object(Object&& other) noexcept
        : name_(std::exchange(other.name_, 0)) {}

    Object& operator=(Object&& other) noexcept {
        if (this != &other) {
            reset();
            name_ = std::exchange(other.name_, 0);
        }
        return *this;
    }

    Object(const Object&) = delete;
    Object& operator=(const Object&) = delete;

    ~Object() { reset(); }

    [[nodiscard]] GLuint name() const { return name_; }

    explicit operator bool() const { return name_ != 0; }

    GLuint release() { return std::exchange(name_, 0); }

    void reset() {
        if (name_ != 0) {
            Traits::destroy(name_);
            name_ = 0;
        }
    }

private:
    GLuint name_ = 0;
};

namespace traits {
struct Texture {
    static void destroy(GLuint n) { glDeleteTextures(1, &n); }
};

struct Buffer {
    static void destroy(GLuint n) { glDeleteBuffers(1, &n); }
};

struct Framebuffer {
    static void destroy(GLuint n) { glDeleteFramebuffers(1, &n); }
};

struct VertexArray {
    static void destroy(GLuint n) { glDeleteVertexArrays(1, &n); }
};

struct Query {
    static void destroy(GLuint n) { glDeleteQueries(1, &n); }
};

struct Program {
    static void destroy(GLuint n) { glDeleteProgram(n); }
};

struct Shader {
    static void destroy(GLuint n) { glDeleteShader(n); }
};
}  // namespace traits

using Texture = Object<traits::Texture>;
using Buffer = Object<traits::Buffer>;
using Framebuffer = Object<traits::Framebuffer>;
using VertexArray = Object<traits::VertexArray>;
using Query = Object<traits::Query>;
using Program = Object<traits::Program>;
using Shader = Object<traits::Shader>;

// Creation through the DSA entry points of GL 4.5.
Texture create_texture(GLenum target);
Buffer create_buffer();
Framebuffer create_framebuffer();
VertexArray create_vertex_array();
Query create_query(GLenum target);

// Textures of one level of immutable storage in `format` (GL_RGBA32F, GL_R16F, ...), sampled as
// GL's defaults say until set_sampling (commands.hpp) says otherwise.
Texture create_texture_1d(GLenum format, int width);
Texture create_texture_2d(GLenum format, int width, int height);
Texture create_texture_3d(GLenum format, int width, int height, int depth);
Texture create_texture_array(GLenum format, int width, int height, int layers);

// A buffer of `bytes` of immutable storage whose content upload() (commands.hpp) replaces.
Buffer create_storage_buffer(std::size_t bytes);

// A framebuffer that draws into `colour` (level 0, colour attachment 0).
Framebuffer create_framebuffer(const Texture& colour);

}  // namespace penumbra::gpu
