#include <penumbra/base/data_dir.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
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

TEST(DemoData, TheHeadCtIsFoundOnlyOnceConverted) {
    const auto cache = std::filesystem::temp_directory_path() / "penumbra_demo_data_test";
    std::filesystem::remove_all(cache);
    const ScopedVariable xdg("XDG_CACHE_HOME", cache.c_str());
    EXPECT_EQ(demo_data_dir(), cache / "penumbra" / "volumes");
    EXPECT_FALSE(demo_ct_path().has_value());
    std::filesystem::create_directories(*demo_data_dir());
    std::ofstream(*demo_data_dir() / "cranium_ct.nrrd") << "NRRD0004\n";
    EXPECT_EQ(demo_ct_path(), cache / "penumbra" / "volumes" / "cranium_ct.nrrd");
    std::filesystem::remove_all(cache);
    const ScopedVariable home("HOME", nullptr);
    const ScopedVariable no_xdg("XDG_CACHE_HOME", nullptr);
    EXPECT_FALSE(demo_data_dir().has_value());
}

}  // namespace
}  // namespace penumbra::base
