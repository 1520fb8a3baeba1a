// flake_test.cpp — flake2d / flake3d (core/device/pmc_flake.h).
//
//  - Against MaterialX's own algorithm (libraries/stdlib/genglsl/lib/
//    mx_flake.glsl), transcribed here separately: GLSL's column-major mat3
//    built and multiplied as columns, the cellnoise calls as MaterialX writes
//    them (mx_cell_noise_float(vec3 / vec4), mx_cell_noise_vec3(vec3 / vec4)).
//  - Analytic properties: coverage 0 has no flake, coverage raises the
//    covered fraction, roughness 0 keeps the normal, the flake normals follow
//    GGX (half of them tilt by less than atan(alpha): P(tan t < a) =
//    a^2 / (alpha^2 + a^2)), azimuths are uniform, id = int(rand (2^24 - 1)).
//  - Through documents on the host reference interpreter: output="..."
//    selects each output, two outputs of one node stay two values, defaults,
//    flake2d = flake3d at (u, v, 0), errors for a missing or unknown output.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/device/pmc_interp.h"
#include "core/error.h"
#include "materials/compiler.h"
#include "materials/mtlx_reader.h"

namespace pmc {
namespace {

// ---- MaterialX's mx_flake, transcribed --------------------------------------

float bits_to_01(pmc_u32 h) { return pmc_noise_to01(h); }
pmc_u32 ifloor(float x) { return pmc_u32(int(std::floor(x))); }
float cell_noise_float3(float3 p) {
  return bits_to_01(pmc_noise_hash3(ifloor(p.x), ifloor(p.y), ifloor(p.z)));
}
float cell_noise_float4(float3 p, float w) {
  return bits_to_01(pmc_noise_hash4(ifloor(p.x), ifloor(p.y), ifloor(p.z), ifloor(w)));
}
// mx_cell_noise_vec3(vec3): seed for 4 words, mix, final(a + i, b, c).
float3 cell_noise_vec3(float3 p) {
  pmc_u32 s = 0xdeadbeefu + (4u << 2) + 13u, a = s + ifloor(p.x), b = s + ifloor(p.y), c = s + ifloor(p.z);
  pmc_noise_bjmix(&a, &b, &c);
  return make_float3(bits_to_01(pmc_noise_bjfinal(a, b, c)), bits_to_01(pmc_noise_bjfinal(a + 1u, b, c)),
                     bits_to_01(pmc_noise_bjfinal(a + 2u, b, c)));
}
// mx_cell_noise_vec3(vec4): seed for 5 words, mix, a += w, final(a, b + i, c).
float3 cell_noise_vec3(float3 p, float w) {
  pmc_u32 s = 0xdeadbeefu + (5u << 2) + 13u, a = s + ifloor(p.x), b = s + ifloor(p.y), c = s + ifloor(p.z);
  pmc_noise_bjmix(&a, &b, &c);
  a += ifloor(w);
  return make_float3(bits_to_01(pmc_noise_bjfinal(a, b, c)), bits_to_01(pmc_noise_bjfinal(a, b + 1u, c)),
                     bits_to_01(pmc_noise_bjfinal(a, b + 2u, c)));
}

struct Mat3 {
  float3 col[3];
};
float3 mul(const Mat3& m, float3 p) { return m.col[0] * p.x + m.col[1] * p.y + m.col[2] * p.z; }

float3 rotate_flake(float3 p, float3 i) {
  const float pi = 3.14159265358979323846f;
  float theta = pi * 2.0f * i.x, phi = pi * 2.0f * i.y, z = i.z * 2.0f;
  float r = std::sqrt(z);
  float vx = std::sin(phi) * r, vy = std::cos(phi) * r, vz = std::sqrt(2.0f - z);
  float s_theta = std::sin(theta), c_theta = std::cos(theta);
  float sx = vx * c_theta - vy * s_theta;
  float sy = vx * s_theta + vy * c_theta;
  // GLSL mat3(a, b, c, d, e, f, g, h, i): columns (a, b, c), (d, e, f), (g, h, i).
  Mat3 m{{make_float3(vx * sx - c_theta, vx * sy - s_theta, vx * vz),
          make_float3(vy * sx + s_theta, vy * sy - c_theta, vy * vz),
          make_float3(vz * sx, vz * sy, 1.0f - z)}};
  return mul(m, p);
}

PmcFlake mx_flake(float size, float roughness, float coverage, float3 position, float3 normal, float3 tangent,
                  float3 bitangent) {
  auto fit = [](float x) {
    float xx = x * x;
    return (-26.19771808f * xx + 26.39663835f * x) /
           (85.53857017f * xx * x + -102.35069432f * xx + -101.42634862f * x + 118.45082288f);
  };
  float probability = fit(std::fmin(std::fmax(coverage, 0.0f), 1.0f));
  const float flake_diameter = 1.5f / std::sqrt(3.0f);
  float3 P = position / size;
  float3 base_P = make_float3(std::floor(P.x), std::floor(P.y), std::floor(P.z));
  float flake_priority = 0.0f;
  float3 flake_cell = make_float3(0, 0, 0);
  for (int i = -1; i < 2; ++i)
    for (int j = -1; j < 2; ++j)
      for (int k = -1; k < 2; ++k) {
        float3 cell_pos = base_P + make_float3(float(i), float(j), float(k));
        float3 PP = P - cell_pos - make_float3(0.5f, 0.5f, 0.5f);
        if (dot(PP, PP) >= flake_diameter * flake_diameter * 3.0f) continue;
        if (cell_noise_float3(cell_pos) > probability) continue;
        float priority = cell_noise_float4(cell_pos, 3.0f);
        if (priority < flake_priority) continue;
        PP = rotate_flake(PP, cell_noise_vec3(cell_pos));
        if (std::fabs(PP.x) <= flake_diameter && std::fabs(PP.y) <= flake_diameter &&
            std::fabs(PP.z) <= flake_diameter) {
          flake_priority = priority;
          flake_cell = cell_pos;
        }
      }
  PmcFlake f{0, 0, 0, normal};
  if (flake_priority <= 0.0f) return f;
  float3 noise = cell_noise_vec3(flake_cell, 2.0f);
  f.rand = noise.z;
  f.id = float(int(noise.z * 16777215.0f));
  f.presence = flake_priority;
  float phi = 3.14159265358979323846f * 2.0f * noise.x;
  float tan_theta = roughness * roughness * std::sqrt(noise.y) / std::sqrt(1.0f - noise.y);
  float sin_theta = tan_theta / std::sqrt(1.0f + tan_theta * tan_theta);
  float cos_theta = std::sqrt(1.0f - sin_theta * sin_theta);
  f.normal = normalize(tangent * std::cos(phi) * sin_theta + bitangent * std::sin(phi) * sin_theta +
                       normal * cos_theta);
  return f;
}

const float3 kN = make_float3(0, 0, 1), kT = make_float3(1, 0, 0), kB = make_float3(0, 1, 0);

TEST(Flake, MatchesMaterialXsAlgorithm) {
  int points = 0, flakes = 0, differ = 0;
  for (float size : {0.01f, 0.05f, 0.3f})
    for (float coverage : {0.2f, 0.5f, 0.9f})
      for (int i = 0; i < 2000; ++i) {
        float3 p = make_float3(0.0137f * float(i % 47) - 0.31f, 0.0071f * float(i / 47) + 0.05f,
                               0.0023f * float(i % 13) - 0.01f);
        float3 n = normalize(make_float3(0.2f, -0.3f, 1.0f));
        float3 t = normalize(cross(kB, n)), b = cross(n, t);
        PmcFlake got = pmc_flake(size, 0.4f, coverage, p, n, t, b);
        PmcFlake want = mx_flake(size, 0.4f, coverage, p, n, t, b);
        ++points;
        flakes += want.presence > 0;
        if (got.id != want.id || got.rand != want.rand || got.presence != want.presence) {
          ++differ;  // a boundary decided by the last bit differently: rare
          continue;
        }
        EXPECT_NEAR(got.normal.x, want.normal.x, 1e-5f);
        EXPECT_NEAR(got.normal.y, want.normal.y, 1e-5f);
        EXPECT_NEAR(got.normal.z, want.normal.z, 1e-5f);
      }
  EXPECT_LE(differ, points / 1000) << differ << " of " << points << " points pick another flake";
  EXPECT_GT(flakes, points / 4);  // the comparison saw flakes, not only empty space
}

// Flakes of a uv grid (flake2d: (u, v, 0)), one entry per distinct flake.
std::map<float, PmcFlake> flakes_of_grid(float size, float roughness, float coverage, int n, int* covered) {
  std::map<float, PmcFlake> by_id;
  *covered = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      PmcFlake f = pmc_flake(size, roughness, coverage,
                             make_float3((float(i) + 0.5f) / float(n), (float(j) + 0.5f) / float(n), 0.0f),
                             kN, kT, kB);
      if (f.presence > 0.0f) {
        ++*covered;
        by_id[f.id] = f;
      }
    }
  return by_id;
}

TEST(Flake, CoverageControlsHowMuchIsCovered) {
  int c0, c2, c5, c10;
  auto none = flakes_of_grid(0.02f, 0.3f, 0.0f, 200, &c0);
  flakes_of_grid(0.02f, 0.3f, 0.2f, 200, &c2);
  flakes_of_grid(0.02f, 0.3f, 0.5f, 200, &c5);
  flakes_of_grid(0.02f, 0.3f, 1.0f, 200, &c10);
  EXPECT_EQ(c0, 0);
  EXPECT_LT(c2, c5);
  EXPECT_LT(c5, c10);
  EXPECT_GT(c10, 200 * 200 / 2);
  // No flake: id, rand, presence 0 and the input normal.
  PmcFlake f = pmc_flake(0.02f, 0.3f, 0.0f, make_float3(0.3f, 0.4f, 0), kN, kT, kB);
  EXPECT_EQ(f.id, 0.0f);
  EXPECT_EQ(f.rand, 0.0f);
  EXPECT_EQ(f.normal.z, 1.0f);
  // A degenerate size has no flakes (and no NaN).
  PmcFlake z = pmc_flake(0.0f, 0.3f, 0.5f, make_float3(0.3f, 0.4f, 0), kN, kT, kB);
  EXPECT_EQ(z.presence, 0.0f);
  EXPECT_EQ(z.normal.z, 1.0f);
}

TEST(Flake, OutputsAreConsistent) {
  int covered;
  auto flakes = flakes_of_grid(0.01f, 0.5f, 0.5f, 300, &covered);
  ASSERT_GT(flakes.size(), 1000u);
  for (const auto& [id, f] : flakes) {
    EXPECT_EQ(f.id, float(int(f.rand * 16777215.0f)));
    EXPECT_GE(f.rand, 0.0f);
    EXPECT_LT(f.rand, 1.0f);
    EXPECT_GT(f.presence, 0.0f);
    EXPECT_LE(f.presence, 1.0f);
    EXPECT_NEAR(length(f.normal), 1.0f, 1e-5f);
  }
  // Roughness 0: every flake normal is the surface normal.
  int c;
  for (const auto& [id, f] : flakes_of_grid(0.01f, 0.0f, 0.5f, 100, &c)) {
    EXPECT_FLOAT_EQ(f.normal.z, 1.0f);
    EXPECT_EQ(f.normal.x, 0.0f);
  }
}

TEST(Flake, NormalsFollowGgx) {
  const float roughness = 0.6f, alpha = roughness * roughness;
  int covered;
  auto flakes = flakes_of_grid(0.004f, roughness, 0.6f, 500, &covered);
  ASSERT_GT(flakes.size(), 4000u);
  int below = 0, front = 0;
  for (const auto& [id, f] : flakes) {
    float tan_t = std::sqrt(f.normal.x * f.normal.x + f.normal.y * f.normal.y) / f.normal.z;
    below += tan_t < alpha;       // P = alpha^2 / (alpha^2 + alpha^2) = 1/2
    front += f.normal.y >= 0.0f;  // uniform azimuth: sin(phi) >= 0 half the time
  }
  const double n = double(flakes.size()), sigma = std::sqrt(0.25 / n);
  EXPECT_NEAR(below / n, 0.5, 4 * sigma);
  EXPECT_NEAR(front / n, 0.5, 4 * sigma);
  // And a quarter below tan = alpha / sqrt(3): P = (a^2 / 3) / (a^2 + a^2 / 3) = 1/4.
  int quarter = 0;
  for (const auto& [id, f] : flakes)
    quarter +=
        std::sqrt(f.normal.x * f.normal.x + f.normal.y * f.normal.y) / f.normal.z < alpha / std::sqrt(3.0f);
  EXPECT_NEAR(quarter / n, 0.25, 4 * std::sqrt(0.1875 / n));
}

// ---- through documents --------------------------------------------------------

struct Params {
  float p[PMC_P_COUNT];
};

Params run(const std::string& nodes, const std::string& inputs, float2 uv, float3 pos) {
  std::string doc = R"(<?xml version="1.0"?><materialx version="1.39">)" + nodes +
                    R"(<standard_surface name="S" type="surfaceshader">)" + inputs +
                    R"(</standard_surface><surfacematerial name="M" type="material">
<input name="surfaceshader" type="surfaceshader" nodename="S"/></surfacematerial></materialx>)";
  std::vector<Graph> graphs = read_mtlx_string(doc, "mem.mtlx");
  if (!graphs[0].error.empty()) throw Error(graphs[0].error);
  TexturePool textures;
  MaterialProgram program;
  const CompiledMaterial& m = compile_material(graphs[0], textures, program);
  PmcShadingInputs in{};
  in.uv = uv;
  in.position = pos;
  in.normal = kN;
  in.tangent = kT;
  in.bitangent = kB;
  PmcTextureSet ts{};
  float stack[PMC_STACK_SIZE];
  Params out;
  pmc_surface_defaults(out.p, in.normal);
  pmc_interp_run(program.code.data(), m.entry, &in, &ts, stack, out.p, nullptr);
  return out;
}

TEST(Flake, DocumentsSelectEachOutput) {
  const std::string nodes =
      R"(<flake2d name="f" type="multioutput"><input name="size" type="float" value="0.05"/><input name="coverage" type="float" value="0.9"/><input name="roughness" type="float" value="0.5"/></flake2d>
<combine3 name="c" type="color3"><input name="in1" type="float" nodename="f" output="rand"/><input name="in2" type="float" nodename="f" output="presence"/><input name="in3" type="integer" nodename="f" output="id"/></combine3>)";
  const std::string inputs = R"(<input name="base_color" type="color3" nodename="c"/>
<input name="normal" type="vector3" nodename="f" output="flakenormal"/>)";
  int on_flake = 0;
  for (int i = 0; i < 64; ++i) {
    float2 uv = make_float2(0.013f * float(i), 0.021f * float(i % 9));
    Params r = run(nodes, inputs, uv, make_float3(0, 0, 0));
    PmcFlake want = pmc_flake(0.05f, 0.5f, 0.9f, make_float3(uv.x, uv.y, 0), kN, kT, kB);
    EXPECT_EQ(r.p[PMC_P_BASE_COLOR], want.rand) << i;
    EXPECT_EQ(r.p[PMC_P_BASE_COLOR + 1], want.presence) << i;
    EXPECT_EQ(r.p[PMC_P_BASE_COLOR + 2], want.id) << i;
    EXPECT_NEAR(r.p[PMC_P_NORMAL], want.normal.x, 1e-6f) << i;
    EXPECT_NEAR(r.p[PMC_P_NORMAL + 2], want.normal.z, 1e-6f) << i;
    on_flake += want.presence > 0 && want.rand != want.presence;
  }
  EXPECT_GT(on_flake, 16);  // rand and presence differ there: two graph nodes, not one
}

TEST(Flake, DefaultsAndFlake2dIsFlake3dInThePlaneZ0) {
  const std::string nodes =
      R"(<flake2d name="f2" type="multioutput"/>
<texcoord name="uv" type="vector2"/>
<convert name="p" type="vector3"><input name="in" type="vector2" nodename="uv"/></convert>
<flake3d name="f3" type="multioutput"><input name="position" type="vector3" nodename="p"/></flake3d>
<combine3 name="c" type="color3"><input name="in1" type="float" nodename="f2" output="rand"/><input name="in2" type="float" nodename="f3" output="rand"/></combine3>)";
  int flakes = 0;
  for (int i = 0; i < 200; ++i) {
    float2 uv = make_float2(0.0031f * float(i), 0.0017f * float(i));
    Params r =
        run(nodes, R"(<input name="base_color" type="color3" nodename="c"/>)", uv, make_float3(5, 6, 7));
    // MaterialX defaults: size 0.01, roughness 0.1, coverage 0.5.
    PmcFlake want = pmc_flake(0.01f, 0.1f, 0.5f, make_float3(uv.x, uv.y, 0), kN, kT, kB);
    EXPECT_EQ(r.p[PMC_P_BASE_COLOR], want.rand);
    EXPECT_EQ(r.p[PMC_P_BASE_COLOR + 1], want.rand);
    flakes += want.presence > 0;
  }
  EXPECT_GT(flakes, 20);
  // flake3d's position defaults to Pobject.
  Params r = run(R"(<flake3d name="f" type="multioutput"/>)",
                 R"(<input name="base_color" type="float" nodename="f" output="presence"/>)",
                 make_float2(0, 0), make_float3(0.123f, 0.456f, 0.789f));
  EXPECT_EQ(r.p[PMC_P_BASE_COLOR],
            pmc_flake(0.01f, 0.1f, 0.5f, make_float3(0.123f, 0.456f, 0.789f), kN, kT, kB).presence);
}

TEST(Flake, ConnectionsMustNameAnOutput) {
  auto error = [](const std::string& connection) {
    try {
      run(R"(<flake2d name="f" type="multioutput"/>)", connection, make_float2(0, 0), make_float3(0, 0, 0));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::string none = error(R"(<input name="base_color" type="float" nodename="f"/>)");
  EXPECT_NE(none.find("has several outputs (id, rand, presence, flakenormal)"), std::string::npos) << none;
  std::string bad = error(R"(<input name="base_color" type="float" nodename="f" output="colour"/>)");
  EXPECT_NE(bad.find("has no output 'colour'"), std::string::npos) << bad;
}

}  // namespace
}  // namespace pmc
