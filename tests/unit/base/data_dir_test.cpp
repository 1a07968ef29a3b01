#include <penumbra/base/data_dir.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

namespace penumbra::base {
namespace {

// Sets an environment variable for one scope and puts back what was there.
class ScopedVariable {
public:
    ScopedVariable(const char* name, const char* value)
        : name_(name) {
        if (const char* old = std::getenv(name); old != nullptr) {
            old_ = old;
        }
        if (value != nullptr) {
            ::setenv(name, value, 1);
        } else {
            ::unsetenv(name);
        }
    }

    ScopedVariable(const ScopedVariable&) = delete;
    ScopedVariable& operator=(const ScopedVariable&) = delete;

    ~ScopedVariable() {
        if (old_) {
            ::setenv(name_, old_->c_str(), 1);
        } else {
            ::unsetenv(name_);
        }
    }

private:
    const char* name_;
    std::optional<std::string> old_;
};

TEST(UserCacheDir, IsUnderXdgCacheHomeElseHomeElseNothing) {
    {
        const ScopedVariable xdg("XDG_CACHE_HOME", "/x");
        const ScopedVariable home("HOME", "/home/u");
        EXPECT_EQ(user_cache_dir(), "/x/penumbra");
    }
    {
        const ScopedVariable xdg("XDG_CACHE_HOME", "");
        const ScopedVariable home("HOME", "/home/u");
        EXPECT_EQ(user_cache_dir(), "/home/u/.cache/penumbra");
    }
    {
        const ScopedVariable xdg("XDG_CACHE_HOME", nullptr);
        const ScopedVariable home("HOME", nullptr);
        EXPECT_FALSE(user_cache_dir().has_value());
    }
}

}  // namespace
}  // namespace penumbra::base
