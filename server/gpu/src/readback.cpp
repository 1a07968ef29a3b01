#include "penumbra/gpu/readback.hpp"

namespace penumbra::gpu {

void AsyncReadback::start(const Texture& texture, GLenum format, GLenum type, std::size_t bytes) {
    if (!buffer_ || capacity_ < bytes) {
        buffer_ = create_buffer();
        // Read by the CPU only: drivers keep such storage where the CPU reads it fastest.
        glNamedBufferStorage(buffer_.name(), static_cast<GLsizeiptr>(bytes), nullptr,
                             GL_MAP_READ_BIT | GL_CLIENT_STORAGE_BIT);
        capacity_ = bytes;
    }
    bytes_ = bytes;
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer_.name());
    // With a pack buffer bound the last argument is an offset into it.
    glGetTextureImage(texture.name(), 0, format, type, static_cast<GLsizei>(bytes), nullptr);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    fence_.insert();
}

base::Status AsyncReadback::read(std::span<std::byte> out) {
    if (auto status = fence_.wait(); !status) {
        bytes_ = 0;
        return status;
    }
    if (bytes_ == 0 || out.size() != bytes_) {
        return base::make_error(base::ErrorCode::gl_error, "no readback of this size was started",
                                "readback");
    }
    glGetNamedBufferSubData(buffer_.name(), 0, static_cast<GLsizeiptr>(bytes_), out.data());
    bytes_ = 0;
    return base::Ok{};
}

}  // namespace penumbra::gpu
