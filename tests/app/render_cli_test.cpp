// render_cli_test.cpp — `pmc render` end to end through the real binary.
//
// Determinism: counter-based random numbers make the image a pure function of
// the seed, so --threads 1 and --threads 2 must give bit-identical EXRs.
// Outputs: EXR + PNG + stats JSON with the promised keys. Bad options: exit
// code 2, a message naming the option, and no output file left behind.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/support/test_support.h"

namespace pmc {
namespace {

const std::string kScene = "data/default/room.obj";

std::string scene() { return test::source_path(kScene); }

TEST(RenderCli, SameSeedGivesBitIdenticalImagesWithOneAndTwoThreads) {
  const std::string dir = test::temp_dir();
  std::string log;
  const std::string common = scene() + " --width 96 --height 64 --spp 4 --max-depth 5 --seed 7 --quiet";
  ASSERT_EQ(test::run_pmc("render " + common + " --threads 1 -o " + dir + "/t1.exr", &log), 0) << log;
  ASSERT_EQ(test::run_pmc("render " + common + " --threads 2 -o " + dir + "/t2.exr", &log), 0) << log;
  Image a = read_image(dir + "/t1.exr"), b = read_image(dir + "/t2.exr");
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  ASSERT_GT(test::image_mean(a), 0.0);
  EXPECT_EQ(0, std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)));
  // And a different seed gives a different image (the comparison can fail).
  ASSERT_EQ(test::run_pmc("render " + scene() +
                              " --width 96 --height 64 --spp 4 --max-depth 5 --seed 8 --quiet -o " + dir +
                              "/t3.exr",
                          &log),
            0);
  Image c = read_image(dir + "/t3.exr");
  EXPECT_NE(0, std::memcmp(a.pixels.data(), c.pixels.data(), a.pixels.size() * sizeof(float)));
}

TEST(RenderCli, WritesExrPngAndStats) {
  const std::string dir = test::temp_dir();
  std::string log;
  ASSERT_EQ(test::run_pmc("render " + scene() + " --width 64 --height 48 --spp 2 -o " + dir +
                              "/img.exr --stats " + dir + "/s.json",
                          &log),
            0)
      << log;
  EXPECT_TRUE(test::file_exists(dir + "/img.exr"));
  Image png = read_image(dir + "/img.png");
  EXPECT_EQ(png.width, 64);
  EXPECT_EQ(png.height, 48);
  std::ifstream in(dir + "/s.json");
  nlohmann::json j = nlohmann::json::parse(in);
  for (const char* key : {"render_seconds", "width", "height", "spp", "paths", "rays", "rays_per_second",
                          "nan_pixels", "stage_seconds", "device"})
    EXPECT_TRUE(j.contains(key)) << key;
  for (const char* stage : {"trace", "shade", "shadow", "film"})
    EXPECT_TRUE(j["stage_seconds"].contains(stage)) << stage;
  // Setup steps: each non-negative, and the total is their sum.
  double sum = 0.0;
  for (const char* step : {"opencl_device", "scene", "materials", "lights", "bvh", "renderer"}) {
    ASSERT_TRUE(j["setup_seconds"].contains(step)) << step;
    EXPECT_GE(j["setup_seconds"][step].get<double>(), 0.0) << step;
    sum += j["setup_seconds"][step].get<double>();
  }
  EXPECT_NEAR(j["setup_seconds"]["total"].get<double>(), sum, 1e-9);
  EXPECT_GT(j["setup_seconds"]["renderer"].get<double>(), 0.0);  // builds an OpenCL program
  EXPECT_EQ(j["paths"].get<long>(), 64 * 48 * 2);
  EXPECT_EQ(j["nan_pixels"].get<long>(), 0);
  EXPECT_NE(log.find("spp"), std::string::npos) << "one-line summary expected";
}

// The stats' "lights" object counts what the scene holds: a strip of N
// emissive triangles (written here) and a lights file of three points. A
// binary tree over its L leaves has 2L - 1 nodes and at least ceil(log2 L)
// levels below its root; the pick by power builds no tree.
TEST(RenderCli, StatsCountTheLightsAndTheTree) {
  const std::string dir = test::temp_dir();
  const int strips = 20;  // 40 emissive triangles
  std::string obj = "mtllib s.mtl\nv -4 0 -4\nv 4 0 -4\nv 4 0 4\nv -4 0 4\nusemtl floor\nf 1 2 3 4\n";
  for (int i = 0; i <= strips; ++i)
    obj += "v " + std::to_string(-2.0 + 0.2 * i) + " 2 0\nv " + std::to_string(-2.0 + 0.2 * i) + " 2 0.5\n";
  obj += "usemtl glow\n";
  for (int i = 0; i < strips; ++i) {
    const int a = 5 + 2 * i;  // this column's two vertices, then the next column's
    obj += "f " + std::to_string(a) + " " + std::to_string(a + 2) + " " + std::to_string(a + 1) + "\n";
    obj += "f " + std::to_string(a + 1) + " " + std::to_string(a + 2) + " " + std::to_string(a + 3) + "\n";
  }
  test::write_file(dir + "/s.obj", obj);
  test::write_file(dir + "/s.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl glow\nKd 0 0 0\nKe 2 2 2\n");
  test::write_file(dir + "/s.lights.json",
                   R"({"lights": [{"type": "point", "position": [0, 1, 0], "intensity": [1, 1, 1]},
                                  {"type": "point", "position": [1, 1, 0], "intensity": [1, 1, 1]},
                                  {"type": "point", "position": [0, 1, 1], "intensity": [1, 1, 1]}]})");
  const std::string common =
      dir + "/s.obj --lights " + dir +
      "/s.lights.json --camera-from 0,3,-6 --camera-at 0,0,0 --width 32 --height 24 --spp 1 "
      "--quiet -o " +
      dir + "/img.exr --stats " + dir + "/s.json";
  std::string log;
  const int leaves = 2 * strips + 3;
  for (const char* sampler : {"on", "off"}) {
    ASSERT_EQ(test::run_pmc("render " + common + " --light-tree " + std::string(sampler), &log), 0) << log;
    std::ifstream in(dir + "/s.json");
    const nlohmann::json j = nlohmann::json::parse(in)["lights"];
    EXPECT_EQ(j["emissive_triangles"].get<int>(), 2 * strips) << sampler;
    EXPECT_EQ(j["count"].get<int>(), leaves) << sampler;  // no environment: --env is black by default
    EXPECT_GE(j["tree_build_seconds"].get<double>(), 0.0) << sampler;
    if (std::string(sampler) == "on") {
      EXPECT_EQ(j["sampler"], "tree");
      EXPECT_EQ(j["tree_nodes"].get<int>(), 2 * leaves - 1);
      EXPECT_GE(j["tree_depth"].get<int>(), int(std::ceil(std::log2(double(leaves)))));
      EXPECT_LT(j["tree_depth"].get<int>(), leaves);
    } else {
      EXPECT_EQ(j["sampler"], "power");
      EXPECT_EQ(j["tree_nodes"].get<int>(), 0);
    }
  }
}

struct BadOption {
  const char* args;
  const char* mentions;
};

// The stats' "memory_bytes" object: a sky map of w x h texels holds its rgb
// texels, the marginal CDF (h), the rows' conditional CDFs (w h), the rows'
// sines (h) and the guide tables (h + 1, then w + 1 a row), as floats,
// counted here from that layout (docs/DESIGN.md), not from pmc's code; the
// cache table is the one the cache object reports; the sum is what the
// process holds at least. Without a map the sky costs nothing.
TEST(RenderCli, StatsListTheMemoryTheRenderHolds) {
  const std::string dir = test::temp_dir();
  const int w = 24, h = 12;
  Image sky;
  sky.width = w;
  sky.height = h;
  sky.channels = 3;
  sky.pixels.assign(size_t(w) * h * 3, 0.5f);
  write_exr(dir + "/sky.exr", sky);
  std::string log;
  const std::string common = scene() + " --mtlx " + test::source_path("data/default/materials.mtlx") +
                             " --cache-model nodes --width 48 --height 32 --spp 2 --quiet";
  ASSERT_EQ(test::run_pmc("render " + common + " --env-map " + dir + "/sky.exr -o " + dir +
                              "/a.exr --stats " + dir + "/a.json",
                          &log),
            0)
      << log;
  ASSERT_EQ(test::run_pmc("render " + common + " -o " + dir + "/b.exr --stats " + dir + "/b.json", &log), 0)
      << log;
  std::ifstream in_a(dir + "/a.json"), in_b(dir + "/b.json");
  const nlohmann::json a = nlohmann::json::parse(in_a), b = nlohmann::json::parse(in_b);
  const nlohmann::json& m = a["memory_bytes"];
  const uint64_t floats = 3u * w * h + h + uint64_t(w) * h + h + (h + 1) + uint64_t(h) * (w + 1);
  EXPECT_EQ(m["sky_map"].get<uint64_t>(), floats * 4u);
  EXPECT_EQ(b["memory_bytes"]["sky_map"].get<uint64_t>(), 0u);
  EXPECT_EQ(m["cache_table"].get<uint64_t>(), a["cache"]["memory_bytes"].get<uint64_t>());
  EXPECT_GT(m["cache_table"].get<uint64_t>(), 0u);  // by node count, this small frame still caches
  EXPECT_GT(m["mesh"].get<uint64_t>(), 0u);
  EXPECT_GT(m["texels"].get<uint64_t>(), 0u);  // its textured materials
  EXPECT_EQ(m["mesh"], b["memory_bytes"]["mesh"]);
  EXPECT_EQ(m["texels"], b["memory_bytes"]["texels"]);
  EXPECT_EQ(m["listed"].get<uint64_t>(), m["mesh"].get<uint64_t>() + m["texels"].get<uint64_t>() +
                                             m["sky_map"].get<uint64_t>() + m["cache_table"].get<uint64_t>());
  EXPECT_GT(m["peak_resident"].get<uint64_t>(), m["listed"].get<uint64_t>());
}

TEST(RenderCli, BadOptionsExitWithCode2AndLeaveNoOutput) {
  const std::string dir = test::temp_dir();
  const BadOption cases[] = {
      {"--width 0", "--width"},
      {"--height -5", "--height"},
      {"--spp 0", "--spp"},
      {"--spp abc", "--spp"},
      {"--max-depth 0", "--max-depth"},
      {"--fov 200", "--fov"},
      {"--env 1,2", "--env"},
      {"--device no-such-device", "no-such-device"},
      {"--no-such-option 3", "--no-such-option"},
      {"--threads 0", "--threads"},
  };
  for (const BadOption& c : cases) {
    std::string log;
    int code = test::run_pmc("render " + scene() + " -o " + dir + "/x.exr --quiet " + c.args, &log);
    EXPECT_EQ(code, 2) << c.args << "\n" << log;
    EXPECT_NE(log.find(c.mentions), std::string::npos) << c.args << "\n" << log;
    EXPECT_FALSE(test::file_exists(dir + "/x.exr")) << c.args;
    EXPECT_FALSE(test::file_exists(dir + "/x.png")) << c.args;
  }
  std::string log;
  EXPECT_EQ(test::run_pmc("render " + dir + "/missing.obj -o " + dir + "/x.exr", &log), 2);
  EXPECT_NE(log.find("missing.obj"), std::string::npos) << log;
}

// MTL statements pmc does not model are named in one warning per material
// (never silently dropped), and the render still succeeds.
TEST(RenderCli, UnmodelledMtlStatementsAreNamedInAWarning) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/m.mtl",
                   "newmtl shiny\nKd 0.5 0.5 0.5\nillum 2\nTf 0.5 0.6 0.7\nmap_Ka glow.png\nmap_Ns ns.png\n"
                   "disp h.png\nPm 0.5\nnewmtl plain\nKd 0.2 0.3 0.4\nillum 7\nNi 1.4\nPm 0.5\n");
  test::write_file(dir + "/a.obj",
                   "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n"
                   "usemtl shiny\nf 1/1 2/2 3/3\nusemtl plain\nf 2/2 4/4 3/3\n");
  std::string log;
  ASSERT_EQ(test::run_pmc(
                "render " + dir + "/a.obj -o " + dir + "/o.exr --width 8 --height 8 --spp 1 --quiet", &log),
            0)
      << log;
  for (const char* what :
       {"material 'shiny': not modelled", "map_Ka glow.png", "map_Ns ns.png", "disp h.png", "Tf 0.5 0.6 0.7"})
    EXPECT_NE(log.find(what), std::string::npos) << what << " in:\n" << log;
  EXPECT_EQ(log.find("PBR extension"), std::string::npos) << "Pm is modelled:\n" << log;
  EXPECT_EQ(log.find("'plain': not modelled"), std::string::npos) << "glass (illum 7) and Pm are modelled:\n"
                                                                  << log;
}

// The default room's MTL stand-ins: the walls read nothing of the shading
// point (uniform: the shade kernel runs them once per batch of hits), the
// floor reads its checker texture by uv.
TEST(InfoCli, BytecodeDumpSaysWhichMaterialsAreUniform) {
  std::string log;
  ASSERT_EQ(
      test::run_pmc("info --scene " + test::source_path("data/default/room.obj") + " --dump-bytecode", &log),
      0)
      << log;
  const size_t walls = log.find("material 'walls'"), floor = log.find("material 'floor'");
  ASSERT_NE(walls, std::string::npos) << log;
  ASSERT_NE(floor, std::string::npos) << log;
  const std::string uniform = "nothing of the shading point (uniform";
  EXPECT_NE(log.substr(walls, log.find("material '", walls + 1) - walls).find(uniform), std::string::npos)
      << log;
  EXPECT_EQ(log.substr(floor, log.find("material '", floor + 1) - floor).find(uniform), std::string::npos)
      << log;
}

TEST(InfoCli, ListsDevices) {
  std::string log;
  ASSERT_EQ(test::run_pmc("info --devices", &log), 0) << log;
  EXPECT_NE(log.find("*"), std::string::npos) << log;
}

// The default scene's cylinder (tiledhexagons, uvtiling 24 x 10, size 0.92):
// its smallest feature is the gap (1 - 0.92) / 24 = 0.00333 uv, two texels
// across it need level ceil(log2(2 / 0.00333)) = 10. The plan shows floors
// with --cache-bandwidth on only.
TEST(InfoCli, CachePlanShowsLevelFloorsWithBandwidthOn) {
  const std::string scene = "info --scene " + test::source_path("data/default/room.obj") + " --mtlx " +
                            test::source_path("data/default/materials.mtlx") + " --dump-cache-plan";
  std::string on, off;
  // The node count alone: at the default 16 spp the cost model drops the
  // cylinder's point (see CachePlanShowsTheCostModelsFigures).
  ASSERT_EQ(test::run_pmc(scene + " --cache-bandwidth on --cache-model nodes", &on), 0) << on;
  EXPECT_NE(on.find("smallest feature 0.00333 uv: texels of at most 0.000977 uv (level >= 10)"),
            std::string::npos)
      << on;
  ASSERT_EQ(test::run_pmc(scene, &off), 0) << off;
  EXPECT_EQ(off.find("smallest feature"), std::string::npos) << off;
  EXPECT_EQ(off.find("level floor"), std::string::npos) << off;
}

// The cost model's figures (the table's costs: the tests set
// PMC_CACHE_COSTS=table). The cylinder's base colour (11 nodes, a 24 x 10
// tiledhexagons) is a marginal point: at 16 spp the expected hit rate is
// 1 - 3.25 / (16 x 1.6) = 87.3% and it does not pay; at 64 spp, with camera
// hits cached in every sample, 1 - 3.625 / (64 x 1.6) = 96.5% and it does
// (in the default first 16: 1 - 3.625 / (16 + 64 x 0.6) = 93.3%). With the
// node count alone it is a point at any samples.
TEST(InfoCli, CachePlanShowsTheCostModelsFigures) {
  const std::string scene = "info --scene " + test::source_path("data/default/room.obj") + " --mtlx " +
                            test::source_path("data/default/materials.mtlx") + " --material cylinder" +
                            " --dump-cache-plan --width 160 --height 90";
  std::string few, many, nodes;
  ASSERT_EQ(test::run_pmc(scene + " --spp 16", &few), 0) << few;
  EXPECT_NE(few.find("cache cost model: table"), std::string::npos) << few;
  EXPECT_NE(few.find("cache points: 0"), std::string::npos) << few;
  EXPECT_NE(few.find("does not pay on this device"), std::string::npos) << few;
  EXPECT_NE(few.find("expected hit rate h 87.3%"), std::string::npos) << few;
  std::string default_camera;
  ASSERT_EQ(test::run_pmc(scene + " --spp 64", &default_camera), 0) << default_camera;
  EXPECT_NE(default_camera.find("camera hits cached in 16 samples: expected hit rate 93.3%"),
            std::string::npos)
      << default_camera;
  ASSERT_EQ(test::run_pmc(scene + " --spp 64 --cache-camera-samples 64", &many), 0) << many;
  EXPECT_NE(many.find("cache points: 1"), std::string::npos) << many;
  EXPECT_NE(many.find("pays: cost C"), std::string::npos) << many;
  EXPECT_NE(many.find("expected hit rate h 96.5%"), std::string::npos) << many;
  EXPECT_NE(many.find("predicted: 1 cache points save"), std::string::npos) << many;
  ASSERT_EQ(test::run_pmc(scene + " --spp 16 --cache-model nodes", &nodes), 0) << nodes;
  EXPECT_NE(nodes.find("cache points: 1"), std::string::npos) << nodes;
  EXPECT_EQ(nodes.find("cache cost model"), std::string::npos) << nodes;
}

}  // namespace
}  // namespace pmc
