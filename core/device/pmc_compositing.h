/* pmc_compositing.h — MaterialX 1.39 compositing nodes on color4 values:
 * premult / unpremult and the merge nodes (disjointover, in, mask, matte,
 * out, over). One lane's float4 operands in, the result out; the interpreter
 * (pmc_interp.h) calls these once per shading point. Shared by the OpenCL
 * interpreter and the host reference (dialect: pmc_vec.h).
 *
 * F, B are the fg / bg colour channels, f, b their alphas (MaterialX
 * Standard Nodes, "Merge Nodes"):
 *   disjointover  RGB F + B            if f + b <= 1
 *                     F + B (1 - f) / b  otherwise (0 where |b| < 1e-6, as
 *                                        MaterialX's GLSL); alpha min(f + b, 1)
 *   in            F b,           alpha f b
 *   mask          B f,           alpha b f
 *   matte         F f + B (1 - f), alpha f + b (1 - f)
 *   out           F (1 - b),     alpha f (1 - b)
 *   over          F + B (1 - f), alpha f + b (1 - f)
 * and every merge node returns mix * result + (1 - mix) * bg.
 *   premult       (RGB a, a)
 *   unpremult     (RGB / a, a); `in` unchanged where a == 0 (the
 *                 specification's rule; MaterialX's GLSL divides by zero)
 */
#ifndef PMC_COMPOSITING_H
#define PMC_COMPOSITING_H

#include "../abi/pmc_bytecode.h"

PMC_FN float4 pmc_composite(float4 fg, float4 bg, float mix, pmc_u32 mode) {
  float4 r;
  if (mode == PMC_COMP_DISJOINTOVER) {
    float sum = fg.w + bg.w;
    if (sum <= 1.0f) {
      r = make_float4(fg.x + bg.x, fg.y + bg.y, fg.z + bg.z, 0.0f);
    } else if (fabs(bg.w) < 1e-6f) {
      r = make_float4(0.0f, 0.0f, 0.0f, 0.0f);
    } else {
      float x = (1.0f - fg.w) / bg.w;
      r = make_float4(fg.x + bg.x * x, fg.y + bg.y * x, fg.z + bg.z * x, 0.0f);
    }
    r.w = fmin(sum, 1.0f);
  } else if (mode == PMC_COMP_IN) {
    r = fg * bg.w;
  } else if (mode == PMC_COMP_MASK) {
    r = bg * fg.w;
  } else if (mode == PMC_COMP_MATTE) {
    float k = 1.0f - fg.w;
    r = make_float4(fg.x * fg.w + bg.x * k, fg.y * fg.w + bg.y * k, fg.z * fg.w + bg.z * k, fg.w + bg.w * k);
  } else if (mode == PMC_COMP_OUT) {
    r = fg * (1.0f - bg.w);
  } else { /* PMC_COMP_OVER */
    r = fg + bg * (1.0f - fg.w);
  }
  return r * mix + bg * (1.0f - mix);
}

/* unpremult != 0 divides, else multiplies, RGB by alpha. */
PMC_FN float4 pmc_premult(float4 in, pmc_u32 unpremult) {
  if (!unpremult) return make_float4(in.x * in.w, in.y * in.w, in.z * in.w, in.w);
  if (in.w == 0.0f) return in;
  return make_float4(in.x / in.w, in.y / in.w, in.z / in.w, in.w);
}

#endif /* PMC_COMPOSITING_H */
