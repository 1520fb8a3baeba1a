/* texture.cl — texture fetches from the shared RGBA8 texel pool.
 *
 * Textures live in one buffer of uchar4 texels (all mip levels of all
 * textures back to back, see PmcTexture). Fetches wrap with the repeat mode
 * (UVs outside [0,1] are common: sponza reaches 18.6) and filter bilinearly;
 * sRGB-encoded textures are decoded through a 256-entry table built on the host.
 * OBJ convention: v = 0 is the bottom row of the image.
 */

static inline int pmc_wrap(int i, int n) {
  int m = i % n;
  return m < 0 ? m + n : m;
}

static inline float4 pmc_texel(__global const uchar4* texels, __constant float* srgb_lut,
                               uint base, int w, int x, int y, int srgb) {
  uchar4 t = texels[base + (uint)y * (uint)w + (uint)x];
  float4 c;
  if (srgb) {
    c = (float4)(srgb_lut[t.x], srgb_lut[t.y], srgb_lut[t.z], (float)t.w * (1.0f / 255.0f));
  } else {
    c = convert_float4(t) * (1.0f / 255.0f);
  }
  return c;
}

/* Bilinear, repeat-wrapped lookup of one mip level. */
static inline float4 pmc_texture_level(__global const PmcTexture* tex, __global const uchar4* texels,
                                       __constant float* srgb_lut, float2 uv, int level) {
  uint base = tex->offset;
  int w = tex->width, h = tex->height;
  for (int l = 0; l < level; ++l) {
    base += (uint)w * (uint)h;
    w = max(1, w >> 1);
    h = max(1, h >> 1);
  }
  /* Keep the fractional part in double-free float math: reduce first so huge
   * UVs (1e7) do not lose all precision before the wrap. */
  float fu = uv.x - floor(uv.x);
  float fv = uv.y - floor(uv.y);
  if (!(fu >= 0.0f && fu < 1.0f)) fu = 0.0f; /* NaN/Inf UVs */
  if (!(fv >= 0.0f && fv < 1.0f)) fv = 0.0f;
  float x = fu * (float)w - 0.5f;
  float y = (1.0f - fv) * (float)h - 0.5f;
  float x0f = floor(x), y0f = floor(y);
  float ax = x - x0f, ay = y - y0f;
  int x0 = pmc_wrap((int)x0f, w), y0 = pmc_wrap((int)y0f, h);
  int x1 = pmc_wrap(x0 + 1, w), y1 = pmc_wrap(y0 + 1, h);
  int srgb = (tex->flags & PMC_TEX_SRGB) != 0u;
  float4 c00 = pmc_texel(texels, srgb_lut, base, w, x0, y0, srgb);
  float4 c10 = pmc_texel(texels, srgb_lut, base, w, x1, y0, srgb);
  float4 c01 = pmc_texel(texels, srgb_lut, base, w, x0, y1, srgb);
  float4 c11 = pmc_texel(texels, srgb_lut, base, w, x1, y1, srgb);
  return mix(mix(c00, c10, ax), mix(c01, c11, ax), ay);
}
