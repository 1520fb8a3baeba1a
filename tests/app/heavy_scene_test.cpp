// heavy_scene_test.cpp — the heavy procedural scene (data/heavy, made by
// scripts/make_heavy_scene.py; the cache's benchmark scene, scripts/bench-heavy).
//
//  * The generator is deterministic and data/heavy is its output: run into a
//    temporary folder, it writes the committed files byte for byte, and no
//    others.
//  * materials.mtlx validates with the MaterialX library's own reader and
//    validator (the materialx Python package in .venv, with its standard
//    libraries) and holds the six materials the OBJ uses; a copy with one
//    input of the wrong type fails the same check.
//  * After pmc's compile (`pmc info --dump-cache-plan`) every material has
//    100-300 nodes, its largest cache point skips at least 50 of them (the
//    heavy sub-graphs are cached), and the scene uses both key kinds.
//  * It renders at a tiny size with the cache off and on (no NaN/Inf, not
//    black, the lights file and camera beside the OBJ found); the cached
//    render has hits on uv and on position keys and its mean is within 5% of
//    the cacheless one's (the cache changes the per-pixel paths, not the
//    light in the room).
// These tests run the project's Python, so the GPU bundle's suite
// (pmc_device_tests) leaves this file out.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "core/image_io.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

const char* const kFiles[] = {"room.obj", "room.mtl", "room.camera", "room.lights.json", "materials.mtlx"};
const std::set<std::string> kMaterials = {"plaster", "wood", "brick", "marble", "metal", "fabric"};

std::string heavy(const std::string& file) { return test::source_path("data/heavy/" + file); }

std::string scene_args() { return heavy("room.obj") + " --mtlx " + heavy("materials.mtlx"); }

// Runs a shell command; returns its exit status, stdout and stderr in `output`.
int run_command(const std::string& cmd, std::string* output) {
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return -1;
  char buf[4096];
  output->clear();
  for (size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) output->append(buf, n);
  const int status = pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(HeavyScene, GeneratorWritesTheCommittedFilesByteForByte) {
  const std::string dir = test::temp_dir() + "/heavy";
  std::string log;
  ASSERT_EQ(run_command(test::source_path("scripts/python") + " " +
                            test::source_path("scripts/make_heavy_scene.py") + " --out " + dir,
                        &log),
            0)
      << log;
  std::set<std::string> generated, committed;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    generated.insert(e.path().filename().string());
  for (const auto& e : std::filesystem::directory_iterator(heavy("")))
    committed.insert(e.path().filename().string());
  EXPECT_EQ(generated, committed) << "data/heavy holds exactly what the generator writes";
  for (const char* f : kFiles) {
    const std::string mine = test::read_file(dir + "/" + f), theirs = test::read_file(heavy(f));
    EXPECT_FALSE(theirs.empty()) << f;
    EXPECT_TRUE(mine == theirs) << f
                                << " differs from the generator's output: run scripts/make_heavy_scene.py";
  }
}

// MaterialX's reader and Document.validate() with the standard libraries
// imported; prints the validation message and the material names.
int validate_with_materialx(const std::string& doc, std::string* output) {
  return run_command(
      test::source_path("scripts/python") +
          " -c \"import MaterialX as mx, os, sys; lib = mx.createDocument(); "
          "mx.loadLibraries(['libraries'], mx.FileSearchPath(os.path.dirname(mx.__file__)), lib); "
          "d = mx.createDocument(); mx.readFromXmlFile(d, sys.argv[1]); d.importLibrary(lib); "
          "ok, msg = d.validate(); print(msg); "
          "print('materials:', ' '.join(m.getName() for m in d.getMaterialNodes())); "
          "sys.exit(0 if ok else 1)\" " +
          doc,
      output);
}

TEST(HeavyScene, MaterialsValidateWithMaterialXsOwnReader) {
  std::string out;
  ASSERT_EQ(validate_with_materialx(heavy("materials.mtlx"), &out), 0) << out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex("materials: ([^\\n]*)"))) << out;
  std::set<std::string> names;
  std::istringstream in(m[1].str());
  for (std::string n; in >> n;) names.insert(n);
  EXPECT_EQ(names, kMaterials);

  // The check can fail: an integer input declared as a float is refused.
  std::string text = test::read_file(heavy("materials.mtlx"));
  const std::string good = "name=\"octaves\" type=\"integer\"";
  const size_t at = text.find(good);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, good.size(), "name=\"octaves\" type=\"float\"");
  const std::string bad = test::temp_dir() + "/bad.mtlx";
  test::write_file(bad, text);
  EXPECT_NE(validate_with_materialx(bad, &out), 0) << out;
}

struct PlannedMaterial {
  int nodes = -1;         // after the last pass
  int largest_point = 0;  // nodes the largest cache point skips
  std::set<std::string> keys;
};

// `pmc info --dump-cache-plan`: per material, nodes after the passes, the largest point, the key kinds.
std::map<std::string, PlannedMaterial> cache_plan() {
  std::string out;
  EXPECT_EQ(test::run_pmc("info --scene " + scene_args() + " --dump-cache-plan", &out), 0) << out;
  std::map<std::string, PlannedMaterial> plans;
  PlannedMaterial* cur = nullptr;
  const std::regex material("^material '([^']+)' \\(.*materials\\.mtlx\\)"), passes("->([0-9]+);\\s*$"),
      point("^    \\+ .*saves a sub-graph of ([0-9]+) nodes, keyed on ([a-z]+)");
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_search(line, m, material)) {
      cur = &plans[m[1].str()];
    } else if (line.rfind("material '", 0) == 0) {
      cur = nullptr;  // MTL materials have no entry here
    } else if (cur && line.find("  passes:") == 0 && std::regex_search(line, m, passes)) {
      cur->nodes = std::stoi(m[1].str());
    } else if (cur && std::regex_search(line, m, point)) {
      cur->largest_point = std::max(cur->largest_point, std::stoi(m[1].str()));
      cur->keys.insert(m[2].str());
    }
  }
  return plans;
}

TEST(HeavyScene, EveryMaterialHas100To300NodesAndItsHeavySubGraphsAreCached) {
  const auto plans = cache_plan();
  std::set<std::string> names, keys;
  for (const auto& [name, p] : plans) {
    names.insert(name);
    keys.insert(p.keys.begin(), p.keys.end());
    EXPECT_GE(p.nodes, 100) << name;
    EXPECT_LE(p.nodes, 300) << name;
    EXPECT_GE(p.largest_point, 50) << name << ": its heavy sub-graph is no cache point";
  }
  EXPECT_EQ(names, kMaterials);
  EXPECT_EQ(keys, (std::set<std::string>{"uv", "position"})) << "both key kinds are used";
}

struct TinyRender {
  Image image;
  nlohmann::json stats;
};

TinyRender render_tiny(const std::string& cache) {
  const std::string base = test::temp_dir() + "/heavy_" + cache;
  std::string log;
  // --cache-model nodes: at 4 spp the cost model rightly keeps the position
  // points out (few samples per cell); this test is about the cache's
  // mechanics on both key kinds (the plan at the benchmark's frame is the
  // test above's).
  EXPECT_EQ(test::run_pmc("render " + scene_args() + " --width 64 --height 36 --spp 4 --seed 5 --cache " +
                              cache + " --cache-model nodes -o " + base + ".exr --stats " + base + ".json",
                          &log),
            0)
      << log;
  EXPECT_EQ(log.find("usemtl"), std::string::npos) << "every usemtl finds its material: " << log;
  TinyRender r;
  r.image = read_image(base + ".exr");
  std::ifstream in(base + ".json");
  r.stats = nlohmann::json::parse(in);
  return r;
}

TEST(HeavyScene, RendersTinyWithTheCacheOffAndOn) {
  const TinyRender off = render_tiny("off"), on = render_tiny("on");
  ASSERT_FALSE(off.image.pixels.empty());
  ASSERT_FALSE(on.image.pixels.empty());
  EXPECT_EQ(test::non_finite(off.image), 0u);
  EXPECT_EQ(test::non_finite(on.image), 0u);
  const double mean_off = test::image_mean(off.image), mean_on = test::image_mean(on.image);
  EXPECT_GT(mean_off, 0.02) << "the room is lit (room.lights.json and room.camera beside the OBJ)";
  EXPECT_NEAR(mean_on / mean_off, 1.0, 0.05);
  const nlohmann::json& c = on.stats["cache"];
  EXPECT_GT(c["position_lookups"].get<uint64_t>(), 0u) << c.dump();
  EXPECT_LT(c["position_lookups"].get<uint64_t>(), c["lookups"].get<uint64_t>()) << "uv lookups too";
  EXPECT_GT(c["uv_hit_rate"].get<double>(), 0.0) << c.dump();
  EXPECT_GT(c["position_hit_rate"].get<double>(), 0.0) << c.dump();
  EXPECT_EQ(off.stats["cache"]["lookups"].get<uint64_t>(), 0u);
}

}  // namespace
}  // namespace pmc
