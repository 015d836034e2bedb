// Viewer scripts (host/app/view_script.h) and settings by name (host/app/view_settings.h).
#include <gtest/gtest.h>

#include <string>

#include "app/view_script.h"
#include "app/view_settings.h"
#include "core/error.h"

namespace {

using namespace nf::app;

std::string error_of(const std::string& text) {
  try {
    parse_script(text, "s.txt");
  } catch (const nf::Error& e) {
    return e.what();
  }
  return "";
}

TEST(ViewScript, ParsesCommandsCommentsAndBlankLines) {
  const Script s = parse_script(
      "# a comment\n\nset spp 16   # trailing comment\norbit 30 -5 10\nzoom 0.5\nframes 4\n"
      "luminaire 1 rotate 0 170 0\nluminaire 0 intensity 2\nsave out.exr\nquit\n",
      "s.txt");
  ASSERT_EQ(s.commands.size(), 8u);
  EXPECT_EQ(s.commands[0].name, "set");
  EXPECT_EQ(s.commands[0].line, 3);
  EXPECT_EQ(s.commands[0].args, (std::vector<std::string>{"spp", "16"}));
  EXPECT_EQ(s.commands[1].args.size(), 3u);
  EXPECT_DOUBLE_EQ(script_number(s, s.commands[1], 1), -5.0);
  EXPECT_EQ(script_integer(s, s.commands[3], 0), 4);
  EXPECT_EQ(s.where(s.commands[6]), "s.txt:9");
}

TEST(ViewScript, ErrorsNameTheLine) {
  EXPECT_NE(error_of("frames 1\nfly 3\n").find("s.txt:2: unknown command 'fly'"), std::string::npos);
  EXPECT_NE(error_of("orbit 1\n").find("s.txt:1: orbit: expected 2 to 3 argument(s), got 1"), std::string::npos);
  EXPECT_NE(error_of("frames 0\n").find("frame count"), std::string::npos);
  EXPECT_NE(error_of("frames two\n").find("s.txt:1"), std::string::npos);
  EXPECT_NE(error_of("zoom 1e999\n").find("not a number"), std::string::npos);
  EXPECT_NE(error_of("zoom -1\n").find("> 0"), std::string::npos);
  EXPECT_NE(error_of("set spp 0\n").find("s.txt:1: set: spp"), std::string::npos);
  EXPECT_NE(error_of("set method best\n").find("best"), std::string::npos);
  EXPECT_NE(error_of("set colour red\n").find("unknown setting 'colour'"), std::string::npos);
  EXPECT_NE(error_of("luminaire 0 scale 2 2 2\n").find("translate, rotate or intensity"), std::string::npos);
  EXPECT_NE(error_of("luminaire 0 translate 1 2\n").find("3 numbers"), std::string::npos);
  EXPECT_NE(error_of("luminaire 0 translate 1 2 3 0\n").find("frame count"), std::string::npos);
  EXPECT_NE(error_of("luminaire 0 intensity 1 2\n").find("1 number"), std::string::npos);
  EXPECT_EQ(error_of("luminaire 0 rotate 0 170 0 12\n"), "");
  EXPECT_NE(error_of("luminaire -1 intensity 2\n").find("index"), std::string::npos);
  EXPECT_NE(error_of("display Z\n").find("image, A, K or VSGL"), std::string::npos);
  EXPECT_NE(error_of("panel maybe\n").find("on or off"), std::string::npos);
  EXPECT_NE(error_of("fov 180\n").find("(0, 179]"), std::string::npos);
  EXPECT_NE(error_of("section stats on\n").find("unknown panel section 'stats'"), std::string::npos);
  EXPECT_EQ(error_of("section statistics on\nsection rendering off\n"), "");
}

// Outputs whose folder is missing fail when the script is read, naming the line (not at the save,
// after the frames have been rendered).
TEST(ViewScript, OutputFoldersAreCheckedWhenTheScriptIsRead) {
  EXPECT_NE(error_of("frames 3\nsave no-such-folder/view.exr\n")
                .find("s.txt:2: save: no-such-folder/view.exr: the folder 'no-such-folder' does not exist"),
            std::string::npos);
  EXPECT_NE(error_of("save-scene no-such-folder/view.json\n").find("s.txt:1: save-scene:"), std::string::npos);
  EXPECT_NE(error_of("\nscreenshot no-such-folder/w.png\n").find("s.txt:2: screenshot:"), std::string::npos);
  // A folder where a file is expected, and a file where a folder is expected.
  const std::string tmp = ::testing::TempDir();
  EXPECT_NE(error_of("save " + tmp + "\n").find("is a folder"), std::string::npos);
  EXPECT_NE(error_of("save /dev/null/view.exr\n").find("is not a folder"), std::string::npos);
  // The working directory and existing folders are fine.
  EXPECT_EQ(error_of("save view.exr\nsave-scene ./view.json\nscreenshot " + tmp + "/w.png\n"), "");
}

TEST(ViewSettings, ApplyByNameValidatesAndLeavesSettingsUnchangedOnError) {
  ViewSettings s;
  apply_setting(s, "spp", "16");
  apply_setting(s, "method", "uniform");
  apply_setting(s, "sampler", "halton_scrambled");
  apply_setting(s, "visibility", "none");
  apply_setting(s, "search_depth", "-1");
  apply_setting(s, "exposure", "2.5");
  apply_setting(s, "scale", "0.5");
  apply_setting(s, "fast_motion", "on");
  EXPECT_EQ(s.frame.sampling.spp, 16);
  EXPECT_EQ(s.frame.sampling.method, nf::render::Method::uniform);
  EXPECT_EQ(s.frame.sampling.sampler, nf::render::SamplerKind::halton_scrambled);
  EXPECT_EQ(s.frame.visibility, nf::render::Visibility::none);
  EXPECT_DOUBLE_EQ(s.frame.tonemap.exposure, 2.5);
  EXPECT_DOUBLE_EQ(s.scale, 0.5);
  EXPECT_TRUE(s.fast_motion);
  const ViewSettings before = s;
  for (const auto& [k, v] : std::vector<std::pair<std::string, std::string>>{{"spp", "0"},
                                                                             {"spp", "16x"},
                                                                             {"search_depth", "0"},
                                                                             {"search_depth", "2000"},
                                                                             {"exposure", "-1"},
                                                                             {"gamma", "nan"},
                                                                             {"scale", "3"},
                                                                             {"shadow_map_size", "8"},
                                                                             {"pause", "perhaps"},
                                                                             {"lanes", "3"},
                                                                             {"nonsense", "1"}}) {
    EXPECT_THROW(apply_setting(s, k, v), nf::Error) << k << "=" << v;
    EXPECT_EQ(s.frame.sampling.spp, before.frame.sampling.spp);
    EXPECT_EQ(s.frame.sampling.search_depth, before.frame.sampling.search_depth);
    EXPECT_EQ(s.scale, before.scale);
  }
}

TEST(ViewSettings, RenderSettingsRoundTripThroughTheSceneStrings) {
  ViewSettings s;
  for (const auto& [k, v] : std::vector<std::pair<std::string, std::string>>{{"method", "paper"},
                                                                             {"sampler", "random"},
                                                                             {"spp", "7"},
                                                                             {"kmax", "3"},
                                                                             {"balance", "min1"},
                                                                             {"search", "binary"},
                                                                             {"search_depth", "9"},
                                                                             {"structure", "fused"},
                                                                             {"visibility", "none"},
                                                                             {"shadow_map_size", "128"},
                                                                             {"seed", "42"},
                                                                             {"exposure", "0.5"},
                                                                             {"gamma", "1.8"}})
    apply_setting(s, k, v);
  const nf::render::FrameSettings back = nf::render::frame_settings(render_settings(s.frame));
  EXPECT_EQ(back.sampling.describe(), s.frame.sampling.describe());
  EXPECT_EQ(back.visibility, s.frame.visibility);
  EXPECT_EQ(back.shadow_map_size, 128);
  EXPECT_DOUBLE_EQ(back.tonemap.exposure, 0.5);
  EXPECT_DOUBLE_EQ(back.tonemap.gamma, 1.8);
}

}  // namespace
