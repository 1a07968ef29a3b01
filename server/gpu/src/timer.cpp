#include "penumbra/gpu/timer.hpp"

namespace penumbra::gpu {

GpuTimer::GpuTimer()
    : query_(create_query(GL_TIME_ELAPSED)) {}

void GpuTimer::begin() {
    glBeginQuery(GL_TIME_ELAPSED, query_.name());
}

void GpuTimer::end() {
    glEndQuery(GL_TIME_ELAPSED);
}

double GpuTimer::milliseconds() const {
    GLuint64 nanoseconds = 0;
    glGetQueryObjectui64v(query_.name(), GL_QUERY_RESULT, &nanoseconds);
    return static_cast<double>(nanoseconds) * 1e-6;
}

}  // namespace penumbra::gpu
