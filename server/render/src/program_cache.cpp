#include "program_cache.hpp"

namespace penumbra::render {

base::Result<const gpu::Program*> ProgramCache::compute(const std::string& file,
                                                        const gpu::Defines& defines) {
    return find_or_build(file, defines, [&] { return shaders_.build_compute(file, defines); });
}

base::Result<const gpu::Program*> ProgramCache::graphics(const std::string& vertex_file,
                                                         const std::string& fragment_file,
                                                         const gpu::Defines& defines) {
    return find_or_build(vertex_file + " " + fragment_file, defines, [&] {
        return shaders_.build_graphics(vertex_file, fragment_file, defines);
    });
}

base::Result<const gpu::Program*> ProgramCache::find_or_build(
        std::string key, const gpu::Defines& defines,
        const std::function<base::Result<gpu::Program>()>& build) {
    for (const auto& [name, value] : defines) {
        key += " " + name + "=" + value;
    }
    if (auto found = programs_.find(key); found != programs_.end()) {
        return &found->second;
    }
    auto built = build();
    if (!built) {
        return built.error();
    }
    return &programs_.emplace(std::move(key), std::move(built.value())).first->second;
}

}  // namespace penumbra::render
