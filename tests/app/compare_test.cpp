// compare_test.cpp — `pmc compare` end to end through the binary.
//
// The brick teapot at 32x24 pixels and 2 samples (well under a second a
// run). Checked against what the command promises, not against recorded
// numbers: the out-dir holds both renders (EXR + PNG), the difference, the
// hit map (PNG + EXR) and metrics.json with every field, whose errors are
// those of the two EXRs it wrote; report.md shows the four pictures and the
// numbers of metrics.json. With --reference-spp or --reference FILE the
// errors against the reference are added (a reference that is the
// cacheless render itself gives zero error for it). Bad input — a reference
// of the wrong size, missing or not an image, a bad --diff-scale, --cache —
// exits with 2 before anything is rendered, names the option and file, and
// leaves no out-dir behind.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "core/image_metrics.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

// The brick teapot (cacheable procedural network), white environment; its
// point planned by node count, as 2 spp is too few samples for it to pay.
std::string teapot() {
  return test::shared_scene("materialx/geometry/teapot.obj") + " --mtlx " +
         test::shared_scene("materialx/standard_surface_brick_procedural.mtlx") +
         " --material M_BrickPattern --env 1,1,1 --camera-from 0.75,1.0,2.45 --camera-at -0.09,0.05,-0.01"
         " --spp 2 --quiet --cache-model nodes";
}
const char* const kSmall = " --width 32 --height 24";

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

// report.md's "| metric | value |" rows.
std::map<std::string, double> report_numbers(const std::string& report) {
  std::map<std::string, double> out;
  std::istringstream in(report);
  for (std::string line; std::getline(in, line);) {
    if (line.size() < 4 || line[0] != '|') continue;
    const size_t mid = line.find(" | ");
    if (mid == std::string::npos) continue;
    const std::string label = line.substr(2, mid - 2), value = line.substr(mid + 3, line.size() - mid - 5);
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (end != value.c_str() && *end == '\0') out[label] = v;
  }
  return out;
}

void expect_close(double reported, double exact, const std::string& what) {
  EXPECT_NEAR(reported, exact, 1e-5 * std::fabs(exact) + 1e-12) << what;
}

void expect_error_fields(const nlohmann::json& e, const std::string& what) {
  for (const char* k : {"rmse", "relmse", "psnr", "max_abs_error"}) {
    ASSERT_TRUE(e.contains(k)) << what << ": " << k;
    EXPECT_TRUE(std::isfinite(e[k].get<double>())) << what << ": " << k;
    EXPECT_GE(e[k].get<double>(), 0.0) << what << ": " << k;
  }
}

TEST(Compare, WritesBothRendersDifferenceHitMapMetricsAndReport) {
  const std::string dir = test::temp_dir() + "/out";
  std::string log;
  ASSERT_EQ(test::run_pmc("compare " + teapot() + kSmall + " --out-dir " + dir, &log), 0) << log;

  for (const char* f : {"cache_off.exr", "cache_on.exr"}) {
    const Image img = read_image(dir + "/" + f);
    EXPECT_EQ(img.width, 32) << f;
    EXPECT_EQ(img.height, 24) << f;
    EXPECT_EQ(img.channels, 3) << f;
  }
  for (const char* f : {"cache_off.png", "cache_on.png", "difference.png"}) {
    const Image img = read_image(dir + "/" + f);
    EXPECT_EQ(img.width, 32) << f;
    EXPECT_EQ(img.height, 24) << f;
  }
  EXPECT_GT(read_image(dir + "/hitmap.png").width, 0) << "the hit map with its colour bar";
  const Image hits = read_image(dir + "/hitmap.exr");
  EXPECT_EQ(hits.width, 32);
  EXPECT_EQ(hits.channels, 1);
  EXPECT_GT(test::image_mean(hits), 0.0) << "the brick network is cached";
  EXPECT_FALSE(test::file_exists(dir + "/reference.exr")) << "no reference asked for";

  const nlohmann::json m = read_json(dir + "/metrics.json");
  EXPECT_EQ(m["width"].get<int>(), 32);
  EXPECT_EQ(m["height"].get<int>(), 24);
  EXPECT_EQ(m["spp"].get<int>(), 2);
  const double t_off = m["time_off_seconds"].get<double>(), t_on = m["time_on_seconds"].get<double>();
  EXPECT_GT(t_off, 0.0);
  EXPECT_GT(t_on, 0.0);
  expect_close(m["speed_ratio"].get<double>(), t_off / t_on, "speed_ratio");
  // The errors are those of the two images it wrote.
  const ImageError e = compare_images(read_image(dir + "/cache_on.exr"), read_image(dir + "/cache_off.exr"));
  expect_close(m["rmse"].get<double>(), e.rmse, "rmse");
  expect_close(m["relmse"].get<double>(), e.relmse, "relmse");
  expect_close(m["psnr"].get<double>(), e.psnr, "psnr");
  expect_close(m["max_abs_error"].get<double>(), e.max_abs, "max_abs_error");
  EXPECT_GT(e.rmse, 0.0) << "the cache changes the image a little";
  expect_error_fields(m["cached_vs_cacheless"], "cached_vs_cacheless");
  EXPECT_EQ(m["cached_vs_cacheless"]["psnr"], m["psnr"]);
  const nlohmann::json& cvc = m["cached_vs_cacheless"];
  expect_close(cvc["worst_tile_psnr"].get<double>(), e.worst_tile_psnr, "worst_tile_psnr");
  expect_close(cvc["worst_trimmed_tile_psnr"].get<double>(), e.worst_trimmed_tile_psnr,
               "worst_trimmed_tile_psnr");
  EXPECT_EQ(cvc["worst_trimmed_tile"], nlohmann::json({e.worst_trimmed_tile_x, e.worst_trimmed_tile_y, 16}));
  EXPECT_GE(e.worst_trimmed_tile_psnr, e.worst_tile_psnr) << "trimming only removes error";
  const double hit_rate = m["hit_rate"].get<double>();
  EXPECT_GT(hit_rate, 0.0);
  EXPECT_LE(hit_rate, 1.0);
  const nlohmann::json& cache = m["cache"];
  EXPECT_TRUE(cache["enabled"].get<bool>());
  EXPECT_GT(cache["hits"].get<double>(), 0.0);
  EXPECT_EQ(cache["hits"].get<uint64_t>() + cache["misses"].get<uint64_t>(),
            cache["lookups"].get<uint64_t>());
  EXPECT_FALSE(cache["size_reason"].get<std::string>().empty());
  EXPECT_EQ(m["cache_memory_bytes"].get<double>(),
            cache["cells"].get<double>() * cache["entries"].get<double>() * 8.0)
      << "cells x entries x 8 bytes";
  EXPECT_FALSE(m.contains("cached_vs_reference"));
  EXPECT_FALSE(m.contains("cacheless_vs_reference"));

  const std::string report = read_text(dir + "/report.md");
  for (const char* img : {"](cache_off.png)", "](cache_on.png)", "](difference.png)", "](hitmap.png)"})
    EXPECT_TRUE(has(report, img)) << img << "\n" << report;
  const std::map<std::string, double> n = report_numbers(report);
  const struct {
    const char* label;
    double value;
  } rows[] = {
      {"time without cache (s)", t_off},
      {"time with cache (s)", t_on},
      {"speed ratio (off / on)", m["speed_ratio"].get<double>()},
      {"PSNR cached vs cacheless (dB)", e.psnr},
      {"RMSE", e.rmse},
      {"relMSE", e.relmse},
      {"max abs error", e.max_abs},
      {"cache hit rate", hit_rate},
      {"cache memory (MiB)", m["cache_memory_bytes"].get<double>() / double(1 << 20)},
  };
  for (const auto& r : rows) {
    ASSERT_TRUE(n.count(r.label)) << r.label << "\n" << report;
    EXPECT_NEAR(n.at(r.label), r.value, 1e-4 * std::fabs(r.value) + 1e-9) << r.label;
  }
}

TEST(Compare, ReferenceSppAddsBothRendersErrorsAgainstIt) {
  const std::string dir = test::temp_dir() + "/out";
  std::string log;
  ASSERT_EQ(test::run_pmc("compare " + teapot() + kSmall + " --reference-spp 4 --out-dir " + dir, &log), 0)
      << log;
  const nlohmann::json m = read_json(dir + "/metrics.json");
  expect_error_fields(m["cached_vs_reference"], "cached_vs_reference");
  expect_error_fields(m["cacheless_vs_reference"], "cacheless_vs_reference");
  EXPECT_EQ(m["reference"]["spp"].get<int>(), 4);
  // The reference it rendered is written and is what the errors were measured against.
  const Image ref = read_image(dir + "/reference.exr");
  EXPECT_EQ(ref.width, 32);
  const ImageError off_ref = compare_images(read_image(dir + "/cache_off.exr"), ref);
  expect_close(m["cacheless_vs_reference"]["relmse"].get<double>(), off_ref.relmse, "relmse vs reference");
  EXPECT_GT(off_ref.relmse, 0.0) << "another seed and sample count: other noise";
  const std::map<std::string, double> n = report_numbers(read_text(dir + "/report.md"));
  ASSERT_TRUE(n.count("relMSE cached vs reference"));
  EXPECT_NEAR(n.at("relMSE cached vs reference"), m["cached_vs_reference"]["relmse"].get<double>(),
              1e-4 * m["cached_vs_reference"]["relmse"].get<double>());
  ASSERT_TRUE(n.count("relMSE cacheless vs reference"));
}

TEST(Compare, ReferenceFileIsMeasuredAgainstBothRenders) {
  const std::string tmp = test::temp_dir(), ref = tmp + "/ref.exr", dir = tmp + "/out";
  std::string log;
  // The cacheless render with the same seed and samples: compare's own
  // cacheless image, so the cacheless error against it is zero.
  ASSERT_EQ(test::run_pmc("render " + teapot() + kSmall + " --cache off -o " + ref, &log), 0) << log;
  ASSERT_EQ(test::run_pmc("compare " + teapot() + kSmall + " --reference " + ref + " --out-dir " + dir, &log),
            0)
      << log;
  const nlohmann::json m = read_json(dir + "/metrics.json");
  expect_error_fields(m["cached_vs_reference"], "cached_vs_reference");
  expect_error_fields(m["cacheless_vs_reference"], "cacheless_vs_reference");
  EXPECT_EQ(m["cacheless_vs_reference"]["rmse"].get<double>(), 0.0);
  EXPECT_EQ(m["cached_vs_reference"], m["cached_vs_cacheless"]);
  EXPECT_EQ(m["reference"]["file"].get<std::string>(), ref);
  EXPECT_FALSE(test::file_exists(dir + "/reference.exr")) << "the given reference is not copied";
  const std::string report = read_text(dir + "/report.md");
  EXPECT_TRUE(has(report, ref)) << report;
  EXPECT_TRUE(report_numbers(report).count("relMSE cacheless vs reference")) << report;
}

// A nested out-dir, so that "not created" covers its parent too.
std::string fresh_out_dir() { return test::temp_dir() + "/new/out"; }
std::string parent(const std::string& dir) { return std::filesystem::path(dir).parent_path().string(); }

TEST(Compare, BadReferenceIsRefusedBeforeRendering) {
  const std::string tmp = test::temp_dir(), ref = tmp + "/ref.exr", text = tmp + "/notes.exr",
                    png = tmp + "/ref.png";  // written beside ref.exr: tone-mapped display values
  std::string log;
  ASSERT_EQ(test::run_pmc("render " + teapot() + kSmall + " --cache off -o " + ref, &log), 0) << log;
  test::write_file(text, "not an image\n");
  const struct {
    std::string args, file, says;
  } cases[] = {
      {" --width 40 --height 24 --reference " + ref, ref, "32x24"},  // wrong size
      {" --width 32 --height 24 --reference " + tmp + "/missing.exr", tmp + "/missing.exr", "does not exist"},
      {" --width 32 --height 24 --reference " + text, text, "cannot read image"},
      {" --width 32 --height 24 --reference " + tmp, tmp, "directory"},
      {" --width 32 --height 24 --reference " + png, png, "not an EXR"},
  };
  for (const auto& c : cases) {
    const std::string dir = tmp + "/new/out";
    EXPECT_EQ(test::run_pmc("compare " + teapot() + c.args + " --out-dir " + dir, &log), 2) << c.args << log;
    EXPECT_TRUE(has(log, "--reference")) << log;
    EXPECT_TRUE(has(log, c.file)) << log;
    EXPECT_TRUE(has(log, c.says)) << log;
    EXPECT_FALSE(test::file_exists(tmp + "/new")) << c.args;
  }
}

TEST(Compare, BadOptionsExitWith2AndCreateNoOutDir) {
  const std::string scene = teapot() + kSmall;
  const struct {
    std::string args, says;
  } cases[] = {
      {" --diff-scale -1", "--diff-scale"},
      {" --diff-scale 0", "--diff-scale"},
      {" --diff-scale nan", "--diff-scale"},
      {" --diff-scale inf", "--diff-scale"},
      {" --cache on", "--cache"},
      {" --reference-spp 0", "--reference-spp"},
      {" --reference-spp 4 --reference x.exr", "--reference"},
      {" --mip-bias 99", "--mip-bias"},  // found while preparing the renders
  };
  for (const auto& c : cases) {
    const std::string dir = fresh_out_dir();
    std::string log;
    EXPECT_EQ(test::run_pmc("compare " + scene + c.args + " --out-dir " + dir, &log), 2) << c.args << log;
    EXPECT_TRUE(has(log, c.says)) << c.args << "\n" << log;
    EXPECT_FALSE(test::file_exists(parent(dir))) << c.args << ": out-dir created";
  }
  // A scene that cannot be loaded.
  const std::string dir = fresh_out_dir();
  std::string log;
  EXPECT_EQ(test::run_pmc("compare " + dir + "/missing.obj --out-dir " + dir, &log), 2) << log;
  EXPECT_TRUE(has(log, "missing.obj")) << log;
  EXPECT_FALSE(test::file_exists(parent(dir))) << "out-dir created";
  // An out-dir that cannot be made: refused before the scene is even loaded.
  const std::string file = test::temp_dir() + "/a_file";
  test::write_file(file, "x\n");
  EXPECT_EQ(test::run_pmc("compare " + dir + "/missing.obj --out-dir " + file + "/out", &log), 2) << log;
  EXPECT_TRUE(has(log, "--out-dir")) << log;
  EXPECT_TRUE(has(log, "is not a folder")) << log;
}

TEST(Compare, AnExistingOutDirAndItsFilesAreLeftAloneOnError) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/mine.txt", "keep me\n");
  std::string log;
  EXPECT_EQ(test::run_pmc("compare " + teapot() + kSmall + " --diff-scale -1 --out-dir " + dir, &log), 2)
      << log;
  EXPECT_TRUE(test::file_exists(dir + "/mine.txt"));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()),
            1);
}

TEST(Compare, HelpListsOnlyWhatCompareAccepts) {
  std::string help;
  ASSERT_EQ(test::run_pmc("compare --help", &help), 0) << help;
  EXPECT_FALSE(has(help, "  --cache on|off")) << "compare refuses --cache\n" << help;
  EXPECT_TRUE(has(help, "always renders both")) << help;
  for (const char* o : {"--out-dir", "--reference REF.exr", "--reference-spp", "--diff-scale",
                        "--cache-cells", "--mip-bias", "--cache-eval", "--width"})
    EXPECT_TRUE(has(help, o)) << o << "\n" << help;
}

}  // namespace
}  // namespace pmc
