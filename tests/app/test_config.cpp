// rayview's settings between runs (app/rayview/state/config.h): written and read back; bad values
// and unknown keys are ignored; a missing file gives the defaults, a FIFO the defaults and a
// reason.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>

#include "state/config.h"

namespace rt::view {
namespace {

TEST(Config, WrittenAndReadBack) {
    const std::string path = ::testing::TempDir() + "rt_config/sub/rayview.conf";
    std::filesystem::remove_all(::testing::TempDir() + "rt_config");
    UserConfig c;
    c.window_w = 1600;
    c.window_h = 900;
    c.ui_scale = 1.5f;
    c.recent = {"/a/b.ray", "/c d/e.ray"};
    ASSERT_TRUE(write_config(path, c));  // the folders are made
    const UserConfig back = read_config(path);
    EXPECT_EQ(back.window_w, 1600);
    EXPECT_EQ(back.window_h, 900);
    EXPECT_EQ(back.ui_scale, 1.5f);
    EXPECT_EQ(back.recent, c.recent);
}

TEST(Config, BadValuesAndAMissingFileGiveTheDefaults) {
    const UserConfig none = read_config(::testing::TempDir() + "rt_no_such_config.conf");
    EXPECT_EQ(none.window_w, 1280);
    EXPECT_TRUE(none.recent.empty());
    const std::string path = ::testing::TempDir() + "rt_bad_config.conf";
    std::ofstream(path) << "window = 10x20000\nui_scale = nan\ncolour = blue\nrecent =\n"
                           "garbage line\nui_scale = 2\n";
    const UserConfig c = read_config(path);
    EXPECT_EQ(c.window_w, 1280);
    EXPECT_EQ(c.window_h, 720);
    EXPECT_EQ(c.ui_scale, 2.0f);
    EXPECT_TRUE(c.recent.empty());
}

TEST(Config, AFifoIsNotWaitedOnButSaid) {
    const std::string path = ::testing::TempDir() + "rt_fifo_config.conf";
    std::filesystem::remove(path);
    ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
    std::string problem;
    const UserConfig c = read_config(path, &problem);  // returns: nothing writes to the FIFO
    EXPECT_EQ(c.window_w, 1280);
    EXPECT_EQ(problem, "'" + path + "' is a FIFO, not a regular file");
    std::string none;
    read_config(::testing::TempDir() + "rt_no_such_config.conf", &none);
    EXPECT_EQ(none, "");  // a first run has no settings yet: nothing to say
    std::filesystem::remove(path);
}

TEST(Config, FollowsXdgConfigHome) {
    setenv("XDG_CONFIG_HOME", "/tmp/xdg-test", 1);
    EXPECT_EQ(config_path(), "/tmp/xdg-test/rayview/rayview.conf");
    unsetenv("XDG_CONFIG_HOME");
    setenv("HOME", "/home/someone", 1);
    EXPECT_EQ(config_path(), "/home/someone/.config/rayview/rayview.conf");
}

}  // namespace
}  // namespace rt::view
