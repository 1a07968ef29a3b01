#include "penumbra/base/secret.hpp"

#include <cctype>
#include <cstddef>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace penumbra::base {

bool same_secret(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) {
        return false;
    }
    unsigned char difference = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        difference |= static_cast<unsigned char>(a[i] ^ b[i]);
    }
    return difference == 0;
}

Result<std::string> read_secret(const std::optional<std::filesystem::path>& file,
                                const char* variable, const std::string& file_where) {
    std::string secret;
    if (file) {
        std::ifstream in(*file);
        if (!in) {
            return make_error(base::ErrorCode::not_found, "cannot read '" + file->string() + "'",
                              file_where);
        }
        std::stringstream text;
        text << in.rdbuf();
        secret = text.str();
    } else if (const char* value = std::getenv(variable); value != nullptr) {
        secret = value;
    } else {
        return std::string();
    }
    while (!secret.empty() && std::isspace(static_cast<unsigned char>(secret.back())) != 0) {
        secret.pop_back();
    }
    if (secret.empty()) {
        return make_error(base::ErrorCode::invalid_argument, "the secret is empty",
                          file ? file_where : std::string(variable));
    }
    return secret;
}

}  // namespace penumbra::base
