#include "penumbra/gpu/context.hpp"

#include <penumbra/base/log.hpp>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <string>
#include <string_view>
#include <vector>

namespace penumbra::gpu {
namespace {

const char* egl_error_name(EGLint code) {
    switch (code) {
        case EGL_SUCCESS:
            return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED:
            return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS:
            return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC:
            return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE:
            return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG:
            return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT:
            return "EGL_BAD_CONTEXT";
        case EGL_BAD_DISPLAY:
            return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH:
            return "EGL_BAD_MATCH";
        case EGL_BAD_PARAMETER:
            return "EGL_BAD_PARAMETER";
        default:
            return "EGL error";
    }
}

std::string egl_failure(const char* call) {
    const EGLint code = eglGetError();
    return std::string(call) + " failed (" + egl_error_name(code) + ")";
}

bool has_extension(const char* list, std::string_view name) {
    if (list == nullptr) {
        return false;
    }
    std::string_view all(list);
    std::size_t start = 0;
    while (start < all.size()) {
        const std::size_t end = all.find(' ', start);
        const std::string_view item = all.substr(start, end - start);
        if (item == name) {
            return true;
        }
        if (end == std::string_view::npos) {
            break;
        }
        start = end + 1;
    }
    return false;
}

void GLAPIENTRY forward_debug_message(GLenum /*source*/, GLenum /*type*/, GLuint id,
                                      GLenum severity, GLsizei length, const GLchar* message,
                                      const void* /*user*/) {
    const std::string text = "GL[" + std::to_string(id) + "] " +
                             std::string(message, length > 0 ? static_cast<std::size_t>(length)
                                                             : std::string_view(message).size());
    switch (severity) {
        case GL_DEBUG_SEVERITY_HIGH:
            base::log_error("gl", text);
            break;
        case GL_DEBUG_SEVERITY_MEDIUM:
            base::log_warning("gl", text);
            break;
        default:
            base::log_debug("gl", text);
            break;
    }
}

struct Attempt {
    EGLDisplay display = EGL_NO_DISPLAY;
    std::string platform;
};

// Every display worth trying, best first: each EGL device, then Mesa's surfaceless platform.
std::vector<Attempt> candidate_displays(std::string& notes) {
    std::vector<Attempt> attempts;
    const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (client_extensions == nullptr) {
        notes += "no EGL client extensions (EGL 1.5 or EGL_EXT_client_extensions missing); ";
        return attempts;
    }
    if (has_extension(client_extensions, "EGL_EXT_platform_device") &&
        has_extension(client_extensions, "EGL_EXT_device_enumeration")) {
        EGLint count = 0;
        eglQueryDevicesEXT(0, nullptr, &count);
        std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count > 0 ? count : 0));
        if (count > 0 && eglQueryDevicesEXT(count, devices.data(), &count) == EGL_TRUE) {
            for (EGLDeviceEXT device : devices) {
                EGLDisplay display =
                        eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
                if (display != EGL_NO_DISPLAY) {
                    attempts.push_back({display, "EGL_EXT_platform_device"});
                }
            }
        }
        if (count <= 0) {
            notes += "EGL_EXT_platform_device lists no device; ";
        }
    } else {
        notes += "EGL_EXT_platform_device not offered; ";
    }
    if (has_extension(client_extensions, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA,
                                                      EGL_DEFAULT_DISPLAY, nullptr);
        if (display != EGL_NO_DISPLAY) {
            attempts.push_back({display, "EGL_MESA_platform_surfaceless"});
        }
    } else {
        notes += "EGL_MESA_platform_surfaceless not offered; ";
    }
    return attempts;
}

}  // namespace

struct Context::State {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    ContextInfo info;

    ~State() {
        if (display != EGL_NO_DISPLAY) {
            eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            if (context != EGL_NO_CONTEXT) {
                eglDestroyContext(display, context);
            }
            eglTerminate(display);
        }
    }
};

Context::Context(std::unique_ptr<State> state)
    : state_(std::move(state)) {}

Context::Context(Context&&) noexcept = default;

Context& Context::operator=(Context&&) noexcept = default;

Context::~Context() = default;

const ContextInfo& Context::info() const {
    return state_->info;
}

base::Status Context::make_current() const {
    if (eglMakeCurrent(state_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, state_->context) !=
        EGL_TRUE) {
        return base::make_error(base::ErrorCode::gl_unavailable, egl_failure("eglMakeCurrent"),
                                "egl");
    }
    return base::Ok{};
}

base::Result<Context> Context::create(const ContextOptions& options) {
    std::string notes;
    // libepoxy loads libEGL lazily; without it every entry point below would abort the process.
    if (!epoxy_has_egl()) {
        return base::make_error(base::ErrorCode::gl_unavailable,
                                "libEGL could not be loaded (install libegl1 and libegl-mesa0, or "
                                "the NVIDIA driver's EGL)",
                                "egl");
    }
    for (const Attempt& attempt : candidate_displays(notes)) {
        auto state = std::make_unique<State>();
        state->display = attempt.display;
        EGLint major = 0;
        EGLint minor = 0;
        if (eglInitialize(attempt.display, &major, &minor) != EGL_TRUE) {
            notes += attempt.platform + ": " + egl_failure("eglInitialize") + "; ";
            state->display = EGL_NO_DISPLAY;
            continue;
        }
        const char* display_extensions = eglQueryString(attempt.display, EGL_EXTENSIONS);
        if (!has_extension(display_extensions, "EGL_KHR_surfaceless_context")) {
            notes += attempt.platform + ": no EGL_KHR_surfaceless_context; ";
            continue;
        }
        if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
            notes += attempt.platform + ": " + egl_failure("eglBindAPI(OpenGL)") + "; ";
            continue;
        }
        const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint config_count = 0;
        const bool no_config_context =
                has_extension(display_extensions, "EGL_KHR_no_config_context");
        if (eglChooseConfig(attempt.display, config_attributes, &config, 1, &config_count) !=
                    EGL_TRUE ||
            config_count == 0) {
            if (!no_config_context) {
                notes += attempt.platform + ": no OpenGL-renderable EGL config; ";
                continue;
            }
            config = nullptr;  // EGL_NO_CONFIG_KHR
        }
        const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                             4,
                                             EGL_CONTEXT_MINOR_VERSION,
                                             5,
                                             EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                             EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                             EGL_CONTEXT_OPENGL_DEBUG,
                                             options.debug ? EGL_TRUE : EGL_FALSE,
                                             EGL_NONE};
        state->context =
                eglCreateContext(attempt.display, config, EGL_NO_CONTEXT, context_attributes);
        if (state->context == EGL_NO_CONTEXT) {
            notes += attempt.platform + ": " + egl_failure("eglCreateContext(OpenGL 4.5 core)") +
                     "; ";
            continue;
        }
        if (eglMakeCurrent(attempt.display, EGL_NO_SURFACE, EGL_NO_SURFACE, state->context) !=
            EGL_TRUE) {
            notes += attempt.platform + ": " + egl_failure("eglMakeCurrent") + "; ";
            continue;
        }
        if (epoxy_gl_version() < 45) {
            notes += attempt.platform + ": OpenGL " + std::to_string(epoxy_gl_version()) +
                     " is older than 4.5; ";
            continue;
        }
        ContextInfo& info = state->info;
        info.platform = attempt.platform;
        info.vendor = reinterpret_cast<const char*>(glGetString(GL_VENDOR));
        info.renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        info.version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
        glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &info.max_3d_texture_size);
        glGetIntegerv(GL_MAX_TEXTURE_SIZE, &info.max_texture_size);
        glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &info.max_array_texture_layers);
        if (options.debug) {
            glEnable(GL_DEBUG_OUTPUT);
            glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
            glDebugMessageCallback(forward_debug_message, nullptr);
        }
        return Context(std::move(state));
    }
    return base::make_error(base::ErrorCode::gl_unavailable,
                            "no usable headless OpenGL 4.5 core context: " +
                                    (notes.empty() ? std::string("no EGL display found") : notes),
                            "egl");
}

}  // namespace penumbra::gpu
