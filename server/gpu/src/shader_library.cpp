#include "penumbra/gpu/shader_library.hpp"

#include <penumbra/base/data_dir.hpp>

#include <cstdlib>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace penumbra::gpu {
namespace {

base::Error shader_error(const std::string& message, const std::string& where) {
    return base::make_error(base::ErrorCode::shader_error, message, where);
}

struct Expander {
    const std::filesystem::path& root;
    const GeneratedFiles& generated;
    ExpandedSource out;
    std::set<std::string> seen;

    // Appends `file` with its includes expanded. Every file is pasted once per program (like
    // #pragma once), which also makes include cycles harmless. `included_from` is "file:line" of
    // the #include that asked for it, for the error message.
    base::Status append(const std::string& file, const std::string& included_from) {
        if (seen.contains(file)) {
            return base::Ok{};
        }
        std::istringstream generated_text;
        std::ifstream file_text;
        std::istream* in = &generated_text;
        if (auto made = generated.find(file); made != generated.end()) {
            generated_text.str(made->second);
        } else {
            file_text.open(root / file);
            if (!file_text) {
                return shader_error("cannot read shader file '" + (root / file).string() + "'",
                                    included_from.empty() ? file : included_from);
            }
            in = &file_text;
        }
        seen.insert(file);
        const std::size_t index = out.files.size();
        out.files.push_back(file);
        static const std::regex include_line(R"(^\s*#\s*include\s+"([^"]+)\"\s*$)");
        out.text += "#line 1 " + std::to_string(index) + "\n";
        std::string line;
        int line_number = 0;
        while (std::getline(*in, line)) {
            ++line_number;
            std::smatch match;
            if (std::regex_match(line, match, include_line)) {
                const std::string here = file + ":" + std::to_string(line_number);
                if (auto status = append(match[1].str(), here); !status) {
                    return status;
                }
                out.text += "#line " + std::to_string(line_number + 1) + " " +
                            std::to_string(index) + "\n";
            } else {
                out.text += line;
                out.text += '\n';
            }
        }
        return base::Ok{};
    }
};

std::string info_log(GLuint object, bool is_program) {
    GLint length = 0;
    if (is_program) {
        glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length);
    } else {
        glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
    }
    std::string log(static_cast<std::size_t>(length > 0 ? length : 0), '\0');
    if (length > 0) {
        if (is_program) {
            glGetProgramInfoLog(object, length, nullptr, log.data());
        } else {
            glGetShaderInfoLog(object, length, nullptr, log.data());
        }
        log.resize(std::string(log.c_str()).size());
    }
    return log;
}

const char* stage_name(GLenum stage) {
    switch (stage) {
        case GL_VERTEX_SHADER:
            return "vertex";
        case GL_FRAGMENT_SHADER:
            return "fragment";
        case GL_COMPUTE_SHADER:
            return "compute";
        default:
            return "shader";
    }
}

base::Result<Program> link(std::initializer_list<const Shader*> shaders, const std::string& what) {
    Program program(glCreateProgram());
    for (const Shader* shader : shaders) {
        glAttachShader(program.name(), shader->name());
    }
    glLinkProgram(program.name());
    GLint linked = GL_FALSE;
    glGetProgramiv(program.name(), GL_LINK_STATUS, &linked);
    if (linked != GL_TRUE) {
        return shader_error("link failed:\n" + info_log(program.name(), true), what);
    }
    return program;
}

}  // namespace

ShaderLibrary::ShaderLibrary(std::filesystem::path root, GeneratedFiles generated)
    : root_(std::move(root))
    , generated_(std::move(generated)) {}

base::Result<ExpandedSource> ShaderLibrary::expand(const std::string& file,
                                                   const Defines& defines) const {
    Expander expander{root_, generated_, {}, {}};
    expander.out.text = "#version 450 core\n";
    for (const auto& [name, value] : defines) {
        expander.out.text += "#define " + name + " " + value + "\n";
    }
    if (auto status = expander.append(file, {}); !status) {
        return status.error();
    }
    return std::move(expander.out);
}

base::Result<Shader> ShaderLibrary::compile(GLenum stage, const std::string& file,
                                            const Defines& defines) const {
    auto source = expand(file, defines);
    if (!source) {
        return source.error();
    }
    Shader shader(glCreateShader(stage));
    const char* text = source->text.c_str();
    glShaderSource(shader.name(), 1, &text, nullptr);
    glCompileShader(shader.name());
    GLint compiled = GL_FALSE;
    glGetShaderiv(shader.name(), GL_COMPILE_STATUS, &compiled);
    if (compiled != GL_TRUE) {
        return shader_error(
                std::string(stage_name(stage)) + " shader failed to compile:\n" +
                        resolve_log_lines(info_log(shader.name(), false), source->files),
                file);
    }
    return shader;
}

base::Result<Program> ShaderLibrary::build_compute(const std::string& file,
                                                   const Defines& defines) const {
    auto shader = compile(GL_COMPUTE_SHADER, file, defines);
    if (!shader) {
        return shader.error();
    }
    return link({&shader.value()}, file);
}

base::Result<Program> ShaderLibrary::build_graphics(const std::string& vertex_file,
                                                    const std::string& fragment_file,
                                                    const Defines& defines) const {
    auto vertex = compile(GL_VERTEX_SHADER, vertex_file, defines);
    if (!vertex) {
        return vertex.error();
    }
    auto fragment = compile(GL_FRAGMENT_SHADER, fragment_file, defines);
    if (!fragment) {
        return fragment.error();
    }
    return link({&vertex.value(), &fragment.value()}, vertex_file + " + " + fragment_file);
}

std::string resolve_log_lines(const std::string& log, const std::vector<std::string>& files) {
    // Mesa: "0:12(3): error: ...", NVIDIA: "0(12) : error C0000: ...".
    static const std::regex mesa(R"(^(\d+):(\d+)\((\d+)\):\s*(.*)$)");
    static const std::regex nvidia(R"(^(\d+)\((\d+)\)\s*:\s*(.*)$)");
    std::istringstream in(log);
    std::string out;
    std::string line;
    const auto file_name = [&](const std::string& index) {
        const std::size_t i = std::stoul(index);
        return i < files.size() ? files[i] : "source " + index;
    };
    while (std::getline(in, line)) {
        std::smatch match;
        if (std::regex_match(line, match, mesa)) {
            out += file_name(match[1].str()) + ":" + match[2].str() + ":" + match[3].str() + ": " +
                   match[4].str();
        } else if (std::regex_match(line, match, nvidia)) {
            out += file_name(match[1].str()) + ":" + match[2].str() + ": " + match[3].str();
        } else {
            out += line;
        }
        out += '\n';
    }
    return out;
}

std::filesystem::path default_shader_dir() {
    if (const char* env = std::getenv("PENUMBRA_SHADER_DIR"); env != nullptr && *env != '\0') {
        return env;
    }
    // Not found: a relative path whose missing files name themselves in the load error.
    return base::data_dir("shaders").value_or(std::filesystem::path("share/penumbra/shaders"));
}

}  // namespace penumbra::gpu
