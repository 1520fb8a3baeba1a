// info_command.cpp — `pmc info`: OpenCL devices, scene summaries, compiled materials.
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "app/cli.h"
#include "app/commands.h"
#include "core/denoiser.h"
#include "core/device/pmc_cache.h"
#include "core/error.h"
#include "core/obj_loader.h"
#include "gpu/cl_context.h"
#include "gpu/device_calibration.h"
#include "gpu/render_config.h"
#include "gpu/render_session.h"
#include "materials/material_set.h"

namespace pmc {
namespace {

std::string node_label(const Graph& g, int n) {
  const Node& node = g.nodes[size_t(n)];
  return (node.name.empty() ? std::string("(") + node.category + ")" : "'" + node.name + "'") + " " +
         node.category + " " + type_name(node.type);
}

void print_cache_plan(const MaterialSet& set, const CompiledMaterial& m, bool bandwidth) {
  const Graph* g = nullptr;
  for (size_t i = 0; i < set.program.materials.size(); ++i)
    if (&set.program.materials[i] == &m) g = &set.graphs[i];
  if (!g) return;
  static const char* enc[] = {"float", "rgb9e5", "half2"};
  std::printf("  cache points: %zu\n", m.cache_plan.points.size());
  for (const CachePoint& cp : m.cache_plan.points) {
    std::printf(
        "    + %s: saves a sub-graph of %d nodes, keyed on %s, stored as %s, K %d sub-sample%s a miss\n",
        node_label(*g, cp.node).c_str(), cp.subgraph_nodes, cache_key_name(cp.key), enc[cp.encoding % 3],
        cp.supersample, cp.supersample == 1 ? "" : "s");
    if (cp.modelled) {
      const PointEconomics& e = cp.economics;
      std::printf(
          "      pays: cost C %.1f unit nodes, expected hit rate h %.1f%%, h C %.1f > lookup L %.1f + (1 - "
          "h) x "
          "miss M %.1f; gain %.1f unit nodes per lookup, %.3f s per frame\n",
          e.cost, 100.0 * e.hit_rate, e.hit_rate * e.cost, e.lookup, e.miss, e.gain, e.frame_seconds);
    }
    if (!bandwidth) continue;  // no floors computed: --cache-bandwidth on shows them
    const char* unit = cp.key == CacheKey::Position ? "scene units" : "uv";
    if (cp.level_floor > PMC_LEVEL_NO_FLOOR)
      std::printf("      smallest feature %.3g %s: texels of at most %.3g %s (level >= %d)\n", cp.feature,
                  unit, std::ldexp(1.0, -cp.level_floor), unit, cp.level_floor);
    else if (!cp.bandwidth_note.empty())
      std::printf("      no level floor: %s\n", cp.bandwidth_note.c_str());
    else
      std::printf("      no level floor: no periodic feature below it\n");
  }
  for (const auto& [n, why] : m.cache_plan.not_cached)
    std::printf("    - %s: %s\n", node_label(*g, n).c_str(), why.c_str());
}

const char* hash_name(SettingHash h) {
  switch (h) {
    case SettingHash::Tag:
      return "tag";
    case SettingHash::Fixed:
      return "fixed";
    case SettingHash::Program:
      return "program";
    case SettingHash::No:
      break;
  }
  return "no";
}

// The table of gpu/render_settings_table.h as JSON (scripts/farm reads the
// defaults from it): each setting's name, flag, type, default (as the flag
// takes it), range ([lo, hi], null for no bound; words: their list), value
// name, help, whether it enters the part's settings hash and how, stats key.
nlohmann::json settings_json() {
  nlohmann::json list = nlohmann::json::array();
  visit_render_settings([&list](const auto& info, auto, auto) {
    using T = std::decay_t<decltype(info.dflt)>;
    nlohmann::json e;
    e["name"] = info.name;
    e["flag"] = info.flag;
    if constexpr (kWordSetting<T>) {
      e["type"] = "word";
      e["words"] = shown_setting_words(info.value);
      e["default"] = setting_words(info.value).at(size_t(frame_value<int>(info.dflt)));
      e["range"] = nullptr;
    } else {
      auto bound = [](double b) { return std::isinf(b) ? nlohmann::json(nullptr) : nlohmann::json(T(b)); };
      e["type"] = std::is_integral_v<T> ? "integer" : "number";
      e["default"] = info.dflt;
      e["range"] = {bound(info.lo), bound(info.hi)};
    }
    e["value"] = info.value;
    e["help"] = info.help;
    e["hashed"] = info.hash == SettingHash::Tag || info.hash == SettingHash::Fixed;
    e["hash"] = hash_name(info.hash);
    e["stats"] = info.stats;
    list.push_back(e);
  });
  return list;
}

struct InfoArgs {
  bool settings = false, denoiser = false;
  bool devices = false, dump_bytecode = false, dump_cache_plan = false;
  std::string scene, material;
  std::string mtlx_library;
  std::vector<std::string> mtlx, mtlx_search_paths;
  // pmc render's defaults (gpu/render_settings_table.h).
  int cache_min_nodes = RenderConfig{}.cache_min_nodes;
  bool cache_position_keys = RenderConfig{}.cache_position_keys;
  bool cache_bandwidth = RenderConfig{}.cache_bandwidth != CacheBandwidth::Off;
  double cache_feature_texels = RenderConfig{}.cache_feature_texels;
  int cache_supersample = RenderConfig{}.cache_supersample;
  // The cost model's frame and device (pmc render's defaults).
  bool cache_cost_model = RenderConfig{}.cache_model == CacheModel::Cost;
  RenderConfig frame;
};

// The cost model's figures for the frame, and what its points save.
void print_cost_model(const CacheCostModel& model) {
  const CacheCosts& c = model.costs;
  const CacheFrame& f = model.frame;
  std::printf("cache cost model: %s\n  unit node %.3g ns; lookup L %.1f unit nodes; miss M %.1f + %.2f x C\n",
              c.source.c_str(), c.unit_ns, c.lookup, c.miss, c.miss_per_cost);
  std::printf(
      "  frame %dx%d, %d spp, max depth %d, camera hits cached in %d samples: expected hit rate %.1f%% (uv), "
      "%.1f%% (position)\n",
      f.width, f.height, f.spp, f.max_depth, std::min(f.spp, f.camera_samples),
      100.0 * expected_hit_rate(f, false), 100.0 * expected_hit_rate(f, true));
}

void print_predicted_savings(const MaterialSet& set, double unit_ns) {
  double saved = 0.0;
  size_t points = 0;
  for (const CompiledMaterial& m : set.program.materials)
    for (const CachePoint& p : m.cache_plan.points) {
      saved += p.economics.frame_seconds;
      ++points;
    }
  std::printf("\npredicted: %zu cache points save %.3f s per frame (%.3g ns a unit node)\n", points, saved,
              unit_ns);
}

int run_info(const InfoArgs& a, const CLI::App& app) {
  if (!a.devices && !a.settings && !a.denoiser && a.scene.empty()) {
    std::printf("%s", app.help().c_str());
    return 2;
  }
  if (a.denoiser) {  // before the rest: scripts/farm asks this before a --denoise job starts
    std::string why;
    if (!denoiser_available(&why)) {
      std::printf("Open Image Denoise: not available: %s\n", why.c_str());
      return 1;
    }
    std::printf("Open Image Denoise: available\n");
    if (!a.devices && !a.settings && a.scene.empty()) return 0;
  }
  if (a.settings) std::printf("%s\n", settings_json().dump(2).c_str());
  if (a.devices) {
    std::vector<ClDeviceInfo> devices = list_cl_devices();
    ClContext chosen;
    for (const ClDeviceInfo& d : devices)
      std::printf("%s %s | %s | %s | %u compute units | %.1f GiB%s\n",
                  d.device_id == chosen.device() ? "*" : " ", d.platform.c_str(), d.name.c_str(),
                  d.version.c_str(), d.compute_units, double(d.global_memory) / double(1ull << 30),
                  d.is_gpu ? " | GPU" : " | CPU");
    std::printf("(* = default device; pick another with --device NAME)\n");
  }
  if (a.dump_bytecode || a.dump_cache_plan) {
    if (a.scene.empty()) fail("--dump-bytecode/--dump-cache-plan need --scene SCENE.obj");
    ObjLoadOptions load;
    load.load_textures = false;
    Scene scene = load_obj(a.scene, load);
    MaterialOptions mo;
    mo.mtlx_files = a.mtlx;
    mo.mtlx.library_dir = a.mtlx_library;
    mo.mtlx.search_paths = a.mtlx_search_paths;
    mo.override_material = a.material;
    mo.compile.cache = true;
    mo.compile.cache_min_nodes = a.cache_min_nodes;
    mo.compile.cache_position_keys = a.cache_position_keys;
    mo.compile.cache_feature_texels = a.cache_bandwidth ? a.cache_feature_texels : 0.0;
    mo.compile.cache_supersample = resolve_supersample(cache_frame(a.frame), a.cache_supersample);
    std::printf("cache sub-samples per miss (--cache-supersample %s): uv %d, position %d\n",
                a.cache_supersample == 0 ? "auto" : std::to_string(a.cache_supersample).c_str(),
                mo.compile.cache_supersample.uv, mo.compile.cache_supersample.position);
    if (a.cache_cost_model) {
      CacheCosts costs;
      try {
        ClContext cl(a.frame.device);
        costs = device_cache_costs(cl);
      } catch (const Error& e) {  // a plan without a device: the table's costs, said so
        warn(std::string("no OpenCL device for the cache's costs (") + e.what() + "): the table's costs");
        costs = default_cache_costs(false);
      }
      mo.compile.cache_model = CacheCostModel{costs, cache_frame(a.frame)};
      print_cost_model(*mo.compile.cache_model);
    }
    MaterialSet set = build_material_set(scene, mo);
    std::printf("bytecode: %zu words for %zu materials\n", set.program.code.size(),
                set.program.materials.size());
    for (const CompiledMaterial& m : set.program.materials) {
      std::printf("\nmaterial '%s' (%s)\n  passes:", m.name.c_str(), m.file.c_str());
      for (const PassStat& ps : m.passes) std::printf(" %s %zu->%zu;", ps.pass.c_str(), ps.before, ps.after);
      std::printf("\n  %u instructions, %u code words, peak stack %u floats\n", m.instructions, m.code_words,
                  m.peak_stack);
      std::printf("  outputs depend on:");
      for (const auto& [input, bits] : m.param_dependencies)
        if (bits) std::printf(" %s=%s", input.c_str(), dependency_names(bits).c_str());
      if (m.uniform) std::printf(" nothing of the shading point (uniform: one run shades a batch of hits)");
      std::printf("\n");
      if (a.dump_cache_plan) print_cache_plan(set, m, a.cache_bandwidth);
      if (a.dump_bytecode) std::printf("%s", disassemble(set.program, m).c_str());
    }
    if (a.dump_cache_plan && mo.compile.cache_model)
      print_predicted_savings(set, mo.compile.cache_model->costs.unit_ns);
    return 0;
  }
  if (!a.scene.empty()) {
    Scene scene = load_obj(a.scene);
    std::printf("scene %s\n  triangles %zu, positions %zu, normals %zu, uvs %zu\n", scene.obj_path.c_str(),
                scene.triangles.size(), scene.positions.size() / 3, scene.normals.size() / 3,
                scene.uvs.size() / 2);
    std::printf("  bounds (%g, %g, %g) .. (%g, %g, %g)\n", scene.bounds.lo[0], scene.bounds.lo[1],
                scene.bounds.lo[2], scene.bounds.hi[0], scene.bounds.hi[1], scene.bounds.hi[2]);
    std::printf("  materials %zu, textures loaded %zu\n", scene.materials.size(), scene.textures.size());
    for (const MtlMaterial& m : scene.materials)
      std::printf("    %-24s Kd %.3g %.3g %.3g  Ks %.3g  Ke %.3g%s%s\n", m.name.c_str(), m.kd[0], m.kd[1],
                  m.kd[2], m.ks[0], m.ke[0], m.map_kd.empty() ? "" : "  map_Kd ", m.map_kd.c_str());
  }
  return 0;
}

}  // namespace

CommandRun add_info_command(CLI::App& pmc) {
  auto a = std::make_shared<InfoArgs>();
  CLI::App* app = pmc.add_subcommand(
      "info",
      "list OpenCL devices (--devices), the render settings (--settings), summarise a scene (--scene)");
  cli::formatter(pmc).usage(
      app,
      "pmc info [--devices] [--settings] [--denoiser] [--scene SCENE.obj [--mtlx F ...] "
      "[--dump-bytecode] [--dump-cache-plan]]",
      "Prints what pmc sees: OpenCL devices, scene contents, compiled materials.");
  app->option_defaults()->group("options");
  app->set_help_flag("-h,--help", "print this help and exit");
  app->add_flag("--devices", a->devices, "list OpenCL platforms and devices");
  app->add_flag("--denoiser", a->denoiser,
                "whether Open Image Denoise (for --denoise) can be loaded, and if not why; exit code 1 "
                "when it cannot");
  app->add_flag("--settings", a->settings,
                "the render settings' table as JSON: name, flag, type, default, range, help, whether the "
                "part hash covers it");
  app->add_option("--scene", a->scene, "summarise a scene: triangles, materials, textures, bounds")
      ->type_name("SCENE.obj");
  app->add_option("--mtlx", a->mtlx, "MaterialX document to bind (repeatable)")
      ->type_name("FILE.mtlx")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app->add_option("--material", a->material, "use this MaterialX material for every triangle")
      ->type_name("NAME");
  app->add_option("--mtlx-library", a->mtlx_library, "MaterialX data libraries (see pmc render --help)")
      ->type_name("DIR");
  app->add_option("--mtlx-search-path", a->mtlx_search_paths,
                  "where MaterialX filenames are looked up (repeatable)")
      ->type_name("DIR")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app->add_flag("--dump-bytecode", a->dump_bytecode,
                "per material: node counts per pass, bytecode, peak stack, dependencies");
  app->add_flag("--dump-cache-plan", a->dump_cache_plan,
                "per material: cache points, the sub-graph each saves, why other nodes are not cached");
  app->add_option("--cache-min-nodes", a->cache_min_nodes,
                  "smallest sub-graph (in nodes) worth a cache point")
      ->type_name("N")
      ->check(cli::at_least(1))
      ->capture_default_str();
  app->add_option_function<std::string>(
         "--cache-model", [a](const std::string& v) { a->cache_cost_model = v == "cost"; },
         "cost: cache points must also pay on the device for the frame below (the figures are shown); "
         "nodes: the node count alone (see pmc render --help)")
      ->type_name("cost|nodes")
      ->check(cli::one_of({"cost", "nodes"}))
      ->default_str("cost");
  app->add_option("--width", a->frame.width, "the frame the cost model plans for (as pmc render)")
      ->type_name("W")
      ->check(cli::at_least(1))
      ->capture_default_str();
  app->add_option("--height", a->frame.height, "(as pmc render)")
      ->type_name("H")
      ->check(cli::at_least(1))
      ->capture_default_str();
  app->add_option("--spp", a->frame.spp, "(as pmc render)")
      ->type_name("N")
      ->check(cli::at_least(1))
      ->capture_default_str();
  app->add_option("--max-depth", a->frame.max_depth, "(as pmc render)")
      ->type_name("D")
      ->check(cli::at_least(1))
      ->capture_default_str();
  app->add_option("--cache-camera-samples", a->frame.cache_camera_samples,
                  "samples whose camera-ray hits use the cache (as pmc render)")
      ->type_name("N")
      ->check(cli::at_least(0))
      ->capture_default_str();
  app->add_option("--device", a->frame.device,
                  "the OpenCL device whose costs the cost model uses (as pmc render)")
      ->type_name("NAME");
  app->add_option_function<std::string>(
         "--cache-keys", [a](const std::string& v) { a->cache_position_keys = v != "uv"; },
         "what cache points are keyed on: uv texels only, or also 3D position cells")
      ->type_name("uv|uv+position")
      ->check(cli::one_of({"uv", "uv+position"}))
      ->default_str("uv+position");
  app->add_option_function<std::string>(
         "--cache-bandwidth", [a](const std::string& v) { a->cache_bandwidth = v != "off"; },
         "level floors from the patterns' feature sizes (see pmc render --help; camera: the same floors)")
      ->type_name("on|camera|off")
      ->check(cli::one_of({"on", "camera", "off"}))
      ->default_str("off");
  app->add_option("--cache-supersample", a->cache_supersample,
                  "sub-samples a cache miss averages over its texel, for the frame above (see pmc render "
                  "--help; 0: auto)")
      ->type_name("N")
      ->check(CLI::IsMember({0, 1, 2, 4, 8, 16}))
      ->capture_default_str();
  app->add_option("--cache-feature-texels", a->cache_feature_texels,
                  "texels across a pattern's smallest feature (see pmc render --help)")
      ->type_name("N")
      ->check(CLI::Range(0.125, 64.0))
      ->capture_default_str();
  return [a, app] { return run_info(*a, *app); };
}

}  // namespace pmc
